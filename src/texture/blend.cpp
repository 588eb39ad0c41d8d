#include "fluidtex/texture/blend.h"

#include <algorithm>
#include <cmath>

#include "fluidtex/util/check.h"

namespace fluidtex {

Blender::Blender(const Exemplar& exemplar, Blend blend) : exemplar_(&exemplar), blend_(blend) {
  if (blend == Blend::Histogram) gaussian_ = &exemplar.gaussian();
}

void Blender::sample(double u, double v, double* term) const {
  float r[3];
  const int nc = channels();
  exemplar_->sample(u, v, r);
  if (gaussian_) {
    gaussian_->to_gaussian(r, term);
    return;
  }
  for (int c = 0; c < nc; ++c)
    term[c] = blend_ == Blend::ContrastPreserving ? static_cast<double>(r[c] - exemplar_->mean()[c]) : r[c];
}

bool Blender::resolve(const double* sum, double sum_w, double sum_w2, float* out) const {
  FLUIDTEX_DCHECK(sum_w > 0.0);
  const int nc = channels();
  double v[3] = {0, 0, 0};
  if (gaussian_) {
    double g[3] = {0, 0, 0};
    for (int c = 0; c < nc; ++c) g[c] = sum[c] / std::sqrt(sum_w2);  // variance preserving
    float colour[3];
    gaussian_->to_colour(g, colour);
    for (int c = 0; c < nc; ++c) v[c] = colour[c];
  } else {
    for (int c = 0; c < nc; ++c)
      v[c] = blend_ == Blend::ContrastPreserving ? sum[c] / std::sqrt(sum_w2) + exemplar_->mean()[c]  // Eq. 7
                                                 : sum[c] / sum_w;
  }
  bool out_of_range = false;
  for (int c = 0; c < nc; ++c) {
    out_of_range = out_of_range || v[c] < 0.0 || v[c] > 1.0;
    out[c] = static_cast<float>(std::clamp(v[c], 0.0, 1.0));
  }
  return out_of_range;
}

}  // namespace fluidtex
