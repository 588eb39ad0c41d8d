/// @file sequence.h
/// @brief A per-frame mesh sequence on disk: which frames exist, and loading
/// one frame with its velocities (read from the file, or derived from the
/// positions of the neighbouring frames by central differences for meshes
/// whose vertex count and order stay constant).
#pragma once

#include <string>
#include <vector>

#include "fluidtex/geometry/mesh.h"
#include "fluidtex/geometry/mesh_clean.h"
#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/util/options.h"

namespace fluidtex {

/// How to read the input sequence.
struct InputOptions {
  std::string pattern;                   ///< -i: frame pattern (####, %04d, $F4)
  std::string frames;                    ///< --frames: "1-120", "1-120x2"; empty = all on disk
  double fps = 24.0;                     ///< frames per second; dt = 1/fps
  std::string velocity_attr;             ///< --velocity-attr; empty = auto-detect
  bool velocity_from_positions = false;  ///< derive velocities by central differences
  bool strict = false;                   ///< reject non-manifold frames instead of carrying on

  /// Every field as f(OptionInfo, field) (util/options.h).
  template <class Self, class F>
  static void for_each_option(Self& o, F&& f) {
    f(OptionInfo{.name = "input",
                 .help = "Input frame pattern: mesh.####.ply, mesh.%04d.ply or mesh.$F4.ply",
                 .alias = "-i"},
      o.pattern);
    f(OptionInfo{.name = "frames", .help = "Frames to use, e.g. 1-120 or 1-120x2 (default: all found)"}, o.frames);
    f(OptionInfo{.name = "fps", .help = "Frames per second; the frame step is 1/fps", .bounds = above(0)}, o.fps);
    f(OptionInfo{.name = "velocity-attr",
                 .help = "Velocity property names 'a,b,c' or a prefix P (P_x or Px...); default: vx vy vz, "
                         "velocity_x..., v_x..."},
      o.velocity_attr);
    f(OptionInfo{.name = "velocity-from-positions",
                 .help = "Derive velocities from neighbouring frames by central differences (constant vertex "
                         "count and order; needed for OBJ input)"},
      o.velocity_from_positions);
    f(OptionInfo{.name = "strict", .help = "Reject non-manifold frames instead of carrying on"}, o.strict);
  }
  void validate() const;
};

class Sequence {
 public:
  /// Resolves the frame list: `options.frames` when given (every frame of the
  /// range must exist: InputError naming the first missing file), otherwise
  /// every frame found on disk (InputError when there is none).
  explicit Sequence(const InputOptions& options);

  const std::vector<int>& frames() const { return frames_; }
  std::size_t size() const { return frames_.size(); }
  std::string path_of(int frame) const { return pattern_.path(frame); }
  const FramePattern& pattern() const { return pattern_; }

  /// Loads frames()[index], cleaned. With velocity_from_positions, velocities
  /// are (p[next] − p[prev]) / (time between them) over the raw vertex order
  /// (one-sided at the ends of the sequence); neighbours with a different
  /// vertex count are an InputError. With `strict`, a non-manifold frame is an
  /// InputError. `report` (optional) receives what cleaning did.
  FrameMesh load(std::size_t index, CleanReport* report = nullptr) const;

 private:
  InputOptions options_;
  FramePattern pattern_;
  std::vector<int> frames_;
};

}  // namespace fluidtex
