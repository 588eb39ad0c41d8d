/// @file info.h
/// @brief `fluidtex info`: what a sequence holds, frame by frame, and what is
/// wrong with it, without writing anything.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fluidtex/geometry/mesh.h"
#include "fluidtex/geometry/mesh_clean.h"
#include "fluidtex/io/sequence.h"

namespace fluidtex {

struct FrameInfo {
  int frame = 0;
  std::string path;
  std::size_t vertices = 0;
  std::size_t faces = 0;
  BBox bbox;
  double area = 0.0;
  double mean_edge = 0.0;
  double speed_min = 0.0, speed_max = 0.0, speed_mean = 0.0;  ///< |v|, scene units / s
  CleanReport clean;
  std::string error;  ///< non-empty when the frame could not be read
};

/// Reads and measures sequence.frames()[index]; a bad frame is reported in
/// `error` instead of throwing.
FrameInfo inspect_frame(const Sequence& sequence, std::size_t index);

/// The texture's size a run gives the sequence by default: the radius from
/// the first readable frame's size, what one exemplar tile spans on the
/// surface then, and that span to two significant digits, the value `info`
/// suggests for --exemplar-size. nullopt when no frame is readable.
struct TextureScale {
  double radius = 0.0;
  double exemplar_size = 0.0;
  double suggested_exemplar_size = 0.0;
};
std::optional<TextureScale> default_texture_scale(const std::vector<FrameInfo>& frames);

/// A human-readable table plus a summary (frames, ranges, problems); the
/// frame rate with where it comes from (Sequence::fps_source()).
std::string format_info(const std::vector<FrameInfo>& frames, double fps, FpsSource fps_source);

/// The same as one JSON document (`fluidtex info --json`): {"sequence",
/// "fps", "fps_source", "frames": [{frame, path, error (null when read), vertices, faces,
/// bbox {min, max}, area, mean_edge, speed {min, max, mean}, clean {...}}],
/// "errors": frames that could not be read, "texture_scale" {radius,
/// exemplar_size, suggested_exemplar_size} (default_texture_scale; absent
/// when no frame is readable)}.
std::string format_info_json(const std::vector<FrameInfo>& frames, double fps, FpsSource fps_source,
                             const std::string& pattern);

}  // namespace fluidtex
