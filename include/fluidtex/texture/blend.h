/// @file blend.h
/// @brief How a texel's overlapping exemplar samples become one colour
/// (Gagnon et al. 2019, Sec. 6.4): each sample enters the texel's sums as a
/// term with its weight w, and the sums resolve to the texel.
///  - `contrast`, Eq. 7 (Yu et al. 2011): R' = Σ w (R − R̂) / √Σw² + R̂,
///    clamped to [0,1]. Keeps the contrast of one patch, but a texel where
///    two structures overlap shows both at once: a third texture.
///  - `linear`: R' = Σ w R / Σ w. Blurs where patches overlap.
///  - `histogram` (beyond the paper, which names the blending function as
///    future work, Sec. 8): the histogram-preserving blend of Heitz and
///    Neyret 2018 ("High-Performance By-Example Noise using a
///    Histogram-Preserving Blending Operator", HPG; Burley 2019). The
///    exemplar's colours are decorrelated (PCA) and each decorrelated channel
///    is mapped through its CDF to a standard normal variable G (tables made
///    once per job: GaussianExemplar, exemplar.h). Samples blend there with
///    variance-preserving weights, G' = Σ w G / √Σw², which keeps G'
///    standard normal, and G' maps back through the inverse CDF: every texel
///    takes a value the exemplar has, with the exemplar's histogram, and no
///    colour leaves its range.
#pragma once

#include <cmath>

#include "fluidtex/texture/exemplar.h"
#include "fluidtex/util/enum_names.h"

namespace fluidtex {

enum class Blend { ContrastPreserving, Linear, Histogram };

inline constexpr EnumName<Blend> kBlendNames[] = {
    {Blend::ContrastPreserving, "contrast"}, {Blend::Linear, "linear"}, {Blend::Histogram, "histogram"}};
constexpr const auto& enum_names(Blend) { return kBlendNames; }
inline const char* to_string(Blend b) { return enum_name(b); }

/// One blend of one exemplar: the term a sample adds to a texel's sums and
/// how the sums resolve. Holds references: the exemplar outlives it.
class Blender {
 public:
  Blender(const Exemplar& exemplar, Blend blend);

  Blend blend() const { return blend_; }
  int channels() const { return exemplar_->channels(); }
  /// The term of the exemplar sample at tile coordinates (u, v) (Exemplar::
  /// sample): R − R̂ (contrast), R (linear) or G (histogram), per channel.
  void sample(double u, double v, double* term) const;
  /// The texel from its sums: `sum` holds Σ w·term per channel, with Σw > 0
  /// and Σw². Clamped to [0,1]; returns true when a channel left it first.
  bool resolve(const double* sum, double sum_w, double sum_w2, float* out) const;

 private:
  const Exemplar* exemplar_;
  const GaussianExemplar* gaussian_ = nullptr;  ///< Histogram only
  Blend blend_;
};

/// The weight a texel blends a sample with under sharpening (Mikkelsen 2022,
/// "Practical Real-Time Hex-Tiling", Sec. 4: weights raised to a power):
/// w' = w_max·(w / w_max)^p for the texel's largest weight w_max. p = 1
/// leaves the weights; larger p narrows the transitions between patches, so
/// more texels show one patch alone.
inline double sharpened(double w, double w_max, double p) {
  if (p == 1.0 || !(w > 0.0)) return w;
  const double t = w / w_max;
  if (p == 2.0) return w_max * t * t;  // the common exponents without pow
  if (p == 3.0) return w_max * t * t * t;
  return w_max * std::pow(t, p);
}

}  // namespace fluidtex
