/// @file frame_texturing.h
/// @brief Texturing one frame and writing it (Sec. 6.4): the exemplar as
/// synthesis reads it, the synthesis settings that follow from a job's
/// options, and a frame's atlas, its layers (frame_layers.h) and its UV mesh,
/// for either method.
#pragma once

#include <string>
#include <vector>

#include "fluidtex/geometry/surface.h"
#include "fluidtex/io/color_spaces.h"
#include "fluidtex/job/frame_stats.h"
#include "fluidtex/job/job_options.h"
#include "fluidtex/texture/exemplar.h"
#include "fluidtex/texture/flowmap.h"
#include "fluidtex/texture/synthesis.h"
#include "fluidtex/tracking/options.h"
#include "fluidtex/tracking/patch.h"

namespace fluidtex {

/// The exemplar as synthesis uses it: read through OpenImageIO, in the
/// working space of `colors` (color_spaces.h), or turned to one channel
/// (Rec. 709 luminance, read_image's rules: heights are data) for
/// displacement. `warning` (when given) says when an unmanaged exemplar
/// names a colour space fluidtex's rules do not know.
Exemplar load_exemplar(const std::string& path, bool displacement, const ColorSpaces& colors = {},
                       std::string* warning = nullptr);

/// What a job's frames are textured from: the exemplar in the working space,
/// and the colour spaces the colour atlas is written in.
struct TextureSource {
  ColorSpaces colors;
  Exemplar exemplar;
};

/// The job's texture source: its colour spaces checked (InputError naming
/// the option), then its exemplar read (load_exemplar). `warning` as there.
TextureSource load_texture_source(const JobOptions& options, std::string* warning = nullptr);

/// The synthesis settings of a job: blend, method, and the exemplar scale
/// and projection tolerance that follow from the resolved tracking lengths.
SynthesisOptions synthesis_options(const TrackingOptions& resolved, const SynthesisJobOptions& so);

/// Scene units one exemplar tile spans on the surface in a job: the tile
/// size at s = 1 (--exemplar-size, else (2 + β)·d) over the uv scale s.
/// The job's atlas options: UDIM tiles (up to kMaxUdimTiles) when --atlas
/// names <UDIM>, one tile otherwise.
AtlasOptions job_atlas_options(const JobOptions& options);

/// What `run` prints, job.toml's [job] table records and every atlas is
/// stamped with (`fluidtex:exemplarSize`).
double exemplar_span(const TrackingOptions& resolved, const SynthesisJobOptions& so);

/// Synthesis of one frame from a tracker's state: atlas, texel map, Eq. 7,
/// then the atlas image, its layers and the UV mesh written atomically.
/// Fills the synthesis numbers and stage seconds of `stats`.
void synthesize_frame(const SurfaceIndex& surface, const std::vector<Patch>& patches, const TrackingOptions& resolved,
                      const TextureSource& source, const JobOptions& options, int frame, FrameStats& stats);

/// The same for the flow-map baseline (flowmap.h): the same atlas, texel
/// map, writers and stats, the texels from the two advected uv sets.
void synthesize_flowmap_frame(const SurfaceIndex& surface, const FlowMapFrame& flow, const TextureSource& source,
                              const JobOptions& options, int frame, FrameStats& stats, double tile_size);

}  // namespace fluidtex
