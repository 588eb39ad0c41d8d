#include "fluidtex/tracking/options.h"

#include <cmath>

#include "fluidtex/util/error.h"

namespace fluidtex {

namespace {

void require(bool ok, const std::string& option, const std::string& what) {
  if (!ok) throw InputError("", "--" + option + " " + what);
}

}  // namespace

void TrackingOptions::validate() const {
  auto finite = [](double v) { return std::isfinite(v); };
  require(finite(radius) && radius >= 0.0, "radius", "must be >= 0 (0 = automatic)");
  require(finite(plane_angle) && plane_angle >= -1.0 && plane_angle < 1.0, "plane-angle", "must be in [-1, 1)");
  require(finite(patch_vertex_angle) && patch_vertex_angle >= -1.0 && patch_vertex_angle < 1.0, "patch-vertex-angle",
          "must be in [-1, 1)");
  require(finite(max_distortion) && max_distortion > 1.0, "max-distortion", "must be > 1");
  require(finite(uv_scale) && uv_scale > 0.0, "uv-scale", "must be > 0");
  require(finite(max_projection) && max_projection >= 0.0, "max-projection", "must be >= 0 (0 = automatic)");
  require(fade_frames >= 1, "fade-frames", "must be >= 1");
  require(finite(thickness) && thickness >= 0.0, "thickness", "must be >= 0 (0 = automatic)");
  require(finite(kill_alpha) && kill_alpha >= 0.0 && kill_alpha < 1.0, "kill-alpha", "must be in [0, 1)");
  require(finite(min_vertex_quality) && min_vertex_quality >= 0.0 && min_vertex_quality <= 1.0, "min-vertex-quality",
          "must be in [0, 1]");
  require(finite(selection_margin) && selection_margin >= 0.0, "selection-margin", "must be >= 0");
}

TrackingOptions TrackingOptions::resolved(double first_frame_diagonal) const {
  TrackingOptions r = *this;
  if (r.radius <= 0.0) r.radius = 0.05 * first_frame_diagonal;
  if (r.max_projection <= 0.0) r.max_projection = 0.25 * r.radius;
  if (r.thickness <= 0.0) r.thickness = 0.25 * r.radius;
  return r;
}

}  // namespace fluidtex
