// The `drop` scene's frames (scene_drop.cpp; not installed).
#pragma once

#include "fluidtex/geometry/mesh.h"
#include "fluidtex/scenes/scene_options.h"

namespace fluidtex::detail {

/// The `drop` scene (scene_drop.cpp): frame is 1-based and already validated.
FrameMesh make_drop_frame(int frame, const SceneOptions& options);

}  // namespace fluidtex::detail
