// The `pour` scene's frames (scene_pour.cpp; not installed).
#pragma once

#include "fluidtex/geometry/mesh.h"
#include "fluidtex/scenes/scene_options.h"

namespace fluidtex::detail {

/// The `pour` scene (scene_pour.cpp): frame is 1-based and already validated.
FrameMesh make_pour_frame(int frame, const SceneOptions& options);

}  // namespace fluidtex::detail
