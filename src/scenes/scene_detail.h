// Internal interface between the scene generators (not installed).
#pragma once

#include "fluidtex/geometry/mesh.h"
#include "fluidtex/scenes/scenes.h"

namespace fluidtex::detail {

/// The `drop` scene (scene_drop.cpp): frame is 1-based and already validated.
FrameMesh make_drop_frame(int frame, const SceneOptions& options);

/// The `drop` scene's voxel size (its level set's, and that of --format vdb).
double drop_voxel_size(const SceneOptions& options);

/// Scene time of a 1-based frame: (frame - 1) / fps.
inline double frame_time(int frame, const SceneOptions& options) {
  return static_cast<double>(frame - 1) / options.fps;
}

/// Duration spanned by the sequence, never below one frame: the time of the
/// last frame, (frames - 1) / fps, or 1 / fps for a single frame.
inline double sequence_duration(const SceneOptions& options) {
  const int steps = options.frames > 1 ? options.frames - 1 : 1;
  return static_cast<double>(steps) / options.fps;
}

}  // namespace fluidtex::detail
