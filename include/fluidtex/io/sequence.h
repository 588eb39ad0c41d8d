/// @file sequence.h
/// @brief A per-frame mesh sequence on disk: which frames exist, and loading
/// one frame with its velocities (read from the file, or derived from the
/// positions of the neighbouring frames by central differences for meshes
/// whose vertex count and order stay constant).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fluidtex/geometry/mesh.h"
#include "fluidtex/geometry/mesh_clean.h"
#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/util/enum_names.h"
#include "fluidtex/util/options.h"
#include "fluidtex/util/shared_options.h"

namespace fluidtex {

/// What a run does with the frames that a stepped range (`1-120x2`) skips.
enum class SkippedFrames {
  Follow,  ///< read them and carry the patches through their velocities, write nothing for them
  Ignore,  ///< one step of v·Δt across the gap: less tracking, but a fast sheet outruns it
};
inline constexpr EnumName<SkippedFrames> kSkippedFramesNames[] = {{SkippedFrames::Follow, "follow"},
                                                                  {SkippedFrames::Ignore, "ignore"}};
constexpr const auto& enum_names(SkippedFrames) { return kSkippedFramesNames; }

/// Where a sequence's frame rate comes from.
enum class FpsSource {
  Given,    ///< --fps
  Header,   ///< the first frame's PLY header states it (read_stated_fps)
  Default,  ///< neither: Sequence::kDefaultFps
};
inline constexpr EnumName<FpsSource> kFpsSourceNames[] = {
    {FpsSource::Given, "given"}, {FpsSource::Header, "header"}, {FpsSource::Default, "default"}};
constexpr const auto& enum_names(FpsSource) { return kFpsSourceNames; }

/// How to read the input sequence.
struct InputOptions {
  std::string pattern;                                   ///< -i: frame pattern (####, %04d, $F4)
  std::string frames;                                    ///< --frames: "1-120", "1-120x2"; empty = all on disk
  SkippedFrames skipped_frames = SkippedFrames::Follow;  ///< --skipped-frames
  std::optional<double> fps;                             ///< frames per second, dt = 1/fps; unset: Sequence::fps()
  std::string velocity_attr;                             ///< --velocity-attr; empty = auto-detect
  bool velocity_from_positions = false;                  ///< derive velocities by central differences
  bool strict = false;                                   ///< reject non-manifold frames instead of carrying on
  std::string vdb_surface;                               ///< .vdb input: level-set grid (empty = auto)
  std::string vdb_velocity;                              ///< .vdb input or --velocity-vdb: velocity grid (empty = auto)
  double vdb_iso = 0.0;                                  ///< .vdb input: iso value of the surface
  double vdb_adaptivity = 0.0;                           ///< .vdb input: volumeToMesh adaptivity
  std::string velocity_vdb;                              ///< take velocities from this VDB frame pattern

  /// Every field as f(OptionInfo, field) (util/options.h): which frames,
  /// then how each is read.
  template <class Self, class F>
  static void for_each_option(Self& o, F&& f) {
    f(shared_options::kInput, o.pattern);
    f(shared_options::kFrames, o.frames);
    f(OptionInfo{.name = "skipped-frames",
                 .help = "Frames a stepped range skips: follow (track through them, each written frame the every-frame "
                         "run's) or ignore"},
      o.skipped_frames);
    for_each_reading_option(o, f);
  }
  /// The options that say how a frame is read (rate, velocities, VDB
  /// grids), without the pattern and the frame range.
  template <class Self, class F>
  static void for_each_reading_option(Self& o, F&& f) {
    f(OptionInfo{.name = "fps",
                 .help = "Frames per second; the frame step is 1/fps (auto: the rate the first frame's PLY header "
                         "states in a comment, as 'fps=30' or 'fps 30', else 24)",
                 .bounds = above(0)},
      o.fps);
    f(OptionInfo{.name = "velocity-attr",
                 .help = "Velocity property names 'a,b,c' or a prefix P (P_x or Px...); default: vx vy vz, "
                         "velocity_x..., v_x..."},
      o.velocity_attr);
    f(OptionInfo{.name = "velocity-from-positions",
                 .help = "Derive velocities from neighbouring frames by central differences (constant vertex "
                         "count and order; needed for OBJ input)"},
      o.velocity_from_positions);
    f(OptionInfo{.name = "strict", .help = "Reject non-manifold frames instead of carrying on"}, o.strict);
    f(OptionInfo{.name = "vdb-surface",
                 .help = "Level-set grid of .vdb input (default: the first level set, or 'surface' or 'phi')"},
      o.vdb_surface);
    f(OptionInfo{.name = "vdb-velocity",
                 .help = "Velocity grid of .vdb input or --velocity-vdb (default: 'vel', 'velocity' or 'v'; "
                         "a staggered grid is sampled as one)"},
      o.vdb_velocity);
    f(OptionInfo{.name = "vdb-iso", .help = "Iso value of the surface in a .vdb level set (world units)"}, o.vdb_iso);
    f(OptionInfo{.name = "vdb-adaptivity",
                 .help = "Mesh adaptivity for .vdb input, 0 (uniform) to 1 (fewest polygons on flat parts)",
                 .bounds = between(0.0, 1.0)},
      o.vdb_adaptivity);
    f(shared_options::kVelocityVdb, o.velocity_vdb);
  }
  void validate() const;
};

class Sequence {
 public:
  /// Resolves the frame list: `options.frames` when given (every frame of the
  /// range must exist: InputError naming the first missing file), otherwise
  /// every frame found on disk (InputError when there is none).
  explicit Sequence(const InputOptions& options);

  /// The frame rate: --fps when given, else the rate the first frame's
  /// header states (stated_fps()), else kDefaultFps.
  double fps() const { return *options_.fps; }
  /// What the first frame's PLY header states in a comment (read_stated_fps()).
  std::optional<double> stated_fps() const { return stated_fps_; }
  /// Where fps() comes from.
  FpsSource fps_source() const { return fps_source_; }
  static constexpr double kDefaultFps = 24.0;

  const std::vector<int>& frames() const { return frames_; }
  std::size_t size() const { return frames_.size(); }
  std::string path_of(int frame) const { return pattern_.path(frame); }
  const FramePattern& pattern() const { return pattern_; }

  /// Loads frames()[index], cleaned. With velocity_vdb, velocities are
  /// sampled from that pattern's file of the same frame number. With
  /// velocity_from_positions, velocities
  /// are (p[next] − p[prev]) / (time between them) over the raw vertex order
  /// (one-sided at the ends of the sequence); neighbours with a different
  /// vertex count are an InputError. With `strict`, a non-manifold frame is an
  /// InputError. `report` (optional) receives what cleaning did.
  FrameMesh load(std::size_t index, CleanReport* report = nullptr) const;

  /// The frames a run steps through to write frames(): those, and, with
  /// SkippedFrames::Follow, every frame on disk (with its velocity VDB when
  /// velocities come from one) that lies between two of them, ascending.
  std::vector<int> followed_frames() const;

  /// This sequence over followed_frames(): the frames a run reads (and
  /// derives velocities from positions over), a copy of this one when
  /// nothing lies between its frames.
  Sequence followed() const;

 private:
  InputOptions options_;
  FramePattern pattern_;
  std::optional<FramePattern> velocity_pattern_;
  std::vector<int> frames_;
  std::optional<double> stated_fps_;
  FpsSource fps_source_ = FpsSource::Given;
};

}  // namespace fluidtex
