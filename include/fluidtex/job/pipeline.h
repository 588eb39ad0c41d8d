/// @file pipeline.h
/// @brief `fluidtex run`: the whole job over a sequence, frame by frame.
#pragma once

#include <cstdint>
#include <string>

#include "fluidtex/io/image_io.h"
#include "fluidtex/io/sequence.h"
#include "fluidtex/io/stats.h"
#include "fluidtex/texture/atlas.h"
#include "fluidtex/texture/flowmap.h"
#include "fluidtex/texture/synthesis.h"
#include "fluidtex/tracking/advection.h"
#include "fluidtex/tracking/options.h"
#include "fluidtex/util/report.h"

namespace fluidtex {

struct OutputOptions {
  std::string dir;            ///< -o: output folder
  std::string atlas_pattern;  ///< --atlas; empty = DIR/atlas.####.exr
  std::string mesh_pattern;   ///< --mesh; empty = DIR/mesh.####.obj
  bool resume = false;        ///< --resume: continue after the last complete frame
  bool debug_views = false;   ///< --debug-views: patch/disk PLYs per frame
  bool write_state = true;    ///< OUT/state/patches.####.bin after every frame

  /// The effective patterns (defaults filled in); InputError when a given
  /// pattern has no frame token or an unsupported extension.
  std::string atlas() const;
  std::string mesh() const;
};

/// How each frame's atlas is made and written (Sec. 6.4).
struct SynthesisJobOptions {
  AtlasOptions atlas;
  Blend blend = Blend::ContrastPreserving;           ///< --blend
  SynthesisMethod method = SynthesisMethod::Raster;  ///< --synthesis
  std::vector<std::string> aov;                      ///< --aov: weight, count, patch
  bool displacement = false;                         ///< --displacement: one-channel height atlas from a grey exemplar
  PixelDepth depth = PixelDepth::Default;            ///< --float for 32-bit EXR/TIFF
  bool track_only = false;                           ///< --track-only: no atlas, no mesh (state and stats only)

  void validate() const;
};

struct JobOptions {
  InputOptions input;
  TexturingMethod method = TexturingMethod::Patches;  ///< --method
  FlowMapOptions flowmap;                             ///< --flowmap-period, --flowmap-axis (--method flowmap)
  TrackingOptions tracking;                           ///< patches; flowmap takes d, β (tile size) and s from it
  SynthesisJobOptions synthesis;
  Advection advection = Advection::Heun;           ///< --advection
  PatchMotion patch_motion = PatchMotion::Smooth;  ///< --patch-motion
  /// Poisson update also seeds where no live patch covers the surface
  /// (docs/method.md); --no-coverage-check leaves it out (paper's plain test).
  bool coverage_check = true;
  OutputOptions output;
  std::string exemplar;  ///< -e: exemplar image
  int threads = 0;       ///< 0 = all cores
  std::uint64_t seed = 1;
  /// The effective configuration as TOML (what --print-config prints),
  /// written to OUT/job.toml when the job starts so that `fluidtex eval`
  /// (and people) can see how the outputs were made; empty = not written.
  std::string manifest;

  /// InputError for any bad option, and for options the method does not
  /// have (flowmap: --resume, --track-only, --debug-views).
  void validate() const;
};

struct JobSummary {
  std::size_t frames = 0;  ///< frames processed by this run
  int resumed_after = -1;  ///< frame whose state the run resumed from, −1 if none
  double seconds = 0.0;
};

/// The state file of `frame` under `dir` (DIR/state/patches.####.bin).
std::string state_path(const std::string& dir, int frame);

/// The exemplar as synthesis uses it: read through OpenImageIO, turned to
/// one channel (Rec. 709 luminance) for displacement.
Exemplar load_exemplar(const std::string& path, bool displacement);

/// The synthesis settings of a job: blend, method, and the exemplar scale
/// and projection tolerance that follow from the resolved tracking lengths.
SynthesisOptions synthesis_options(const TrackingOptions& resolved, const SynthesisJobOptions& so);

/// Synthesis of one frame from a tracker's state: atlas, texel map, Eq. 7,
/// then the atlas image (and AOVs) and the UV mesh written atomically.
/// Fills the synthesis numbers and stage seconds of `stats`.
void synthesize_frame(const SurfaceIndex& surface, const std::vector<Patch>& patches, const TrackingOptions& resolved,
                      const Exemplar& exemplar, const JobOptions& options, int frame, FrameStats& stats);

/// The same for the flow-map baseline (flowmap.h): the same atlas, texel
/// map, writers and stats, the texels from the two advected uv sets.
void synthesize_flowmap_frame(const SurfaceIndex& surface, const FlowMapFrame& flow, const Exemplar& exemplar,
                              const JobOptions& options, int frame, FrameStats& stats);

/// Runs the job (either method). Throws InputError for bad input (before any output is
/// written when the problem can be seen up front), InternalError otherwise.
JobSummary run_job(const JobOptions& options, Reporter& reporter);

}  // namespace fluidtex
