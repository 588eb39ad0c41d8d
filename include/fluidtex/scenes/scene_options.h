/// @file scene_options.h
/// @brief What every example scene is made with (scenes.h): its length,
/// frame rate, mesh density and file format, and the scene time of a frame.
#pragma once

#include <string>

#include "fluidtex/util/options.h"
#include "fluidtex/util/shared_options.h"

namespace fluidtex {

struct SceneOptions {
  int frames = 48;    ///< number of frames written (1..frames)
  double fps = 24.0;  ///< frame rate the velocities refer to
  /// Mesh density: cells across the scene's extent (2D: grid cells across the
  /// domain; 3D: voxels across the domain). Face counts grow as resolution²
  /// for all scenes.
  int resolution = 64;
  /// File format written by write_scene: "ply" (x y z vx vy vz) or "vdb" (a
  /// level set `surface` and a velocity grid `vel`; the 3D scenes only, drop
  /// and pour, whose surfaces are closed).
  std::string format = "ply";
  bool staggered = false;  ///< vdb: write the velocity as a staggered (MAC) grid

  /// Every field as f(OptionInfo, field) (util/options.h).
  template <class Self, class F>
  static void for_each_option(Self& o, F&& f) {
    f(OptionInfo{.name = shared_options::kFrames.name, .help = "Number of frames", .bounds = at_least(1)}, o.frames);
    f(OptionInfo{.name = "fps", .help = "Frames per second", .bounds = above(0)}, o.fps);
    f(OptionInfo{.name = "resolution",
                 .help = "Mesh density: grid cells (2D) or voxels (3D) across the domain",
                 .bounds = at_least(4)},
      o.resolution);
    f(OptionInfo{.name = "format",
                 .help = "ply (x y z vx vy vz) or vdb (level set 'surface' and velocity grid 'vel'; 3D scenes: drop, "
                         "pour)",
                 .choices = "ply,vdb"},
      o.format);
    f(OptionInfo{.name = "staggered", .help = "vdb: write the velocity as a staggered (MAC) grid"}, o.staggered);
  }

  /// Scene time of a 1-based frame: (frame - 1) / fps.
  double time_of(int frame) const { return static_cast<double>(frame - 1) / fps; }

  /// Duration spanned by the sequence, never below one frame: the time of
  /// the last frame, (frames - 1) / fps, or 1 / fps for a single frame.
  double duration() const { return static_cast<double>(frames > 1 ? frames - 1 : 1) / fps; }
};

}  // namespace fluidtex
