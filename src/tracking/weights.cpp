#include "fluidtex/tracking/weights.h"

#include <algorithm>

namespace fluidtex {

double tail_weight(double r, const TrackingOptions& options) {
  const double reach = (1.0 + options.selection_margin) * options.d();
  return kCoverageTail * std::max(0.0, 1.0 - r / reach);
}

double radial_weight(double r, const TrackingOptions& options) {
  return std::max(0.0, 1.0 - r / options.d()) + tail_weight(r, options);  // d_uv = d
}

float core_weight(const Patch& patch, std::size_t v, double radius, double uv_scale) {
  const double radial = std::max(0.0, 1.0 - patch.uvs[v].norm() / radius);  // d_uv = d, p_uv is the origin
  const double ks =
      radial * uv_scale * (patch.border[v] ? 0.0 : 1.0) * std::max(0.0, shown_quality(patch, v));  // Eq. 4
  return static_cast<float>(ks * patch.kt);                                                        // Eq. 2
}

void update_weights(Patch& patch, const TrackingOptions& options) {
  const std::size_t nv = patch.positions.size();
  patch.weight.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    const double quality = std::max(shown_quality(patch, v), kCoverageTail);
    const double r = patch.uvs[v].norm();  // p_uv is the origin
    // d_V = 0 on the border takes the disk's term (Eq. 4), not the tail.
    const double ks =
        (patch.border[v] ? tail_weight(r, options) : radial_weight(r, options)) * options.uv_scale * quality;
    patch.weight[v] = static_cast<float>(ks * patch.kt);  // Eq. 2
  }
}

}  // namespace fluidtex
