/// @file scene_options.h
/// @brief What every example scene is made with (scenes.h): its length,
/// frame rate, mesh density and file format, and the scene time of a frame.
#pragma once

#include <string>

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

  /// Scene time of a 1-based frame: (frame - 1) / fps.
  double time_of(int frame) const { return static_cast<double>(frame - 1) / fps; }

  /// Duration spanned by the sequence, never below one frame: the time of
  /// the last frame, (frames - 1) / fps, or 1 / fps for a single frame.
  double duration() const { return static_cast<double>(frames > 1 ? frames - 1 : 1) / fps; }
};

}  // namespace fluidtex
