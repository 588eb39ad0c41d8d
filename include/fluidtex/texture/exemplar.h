/// @file exemplar.h
/// @brief The exemplar texture as the synthesis samples it: linear float,
/// bilinear, tiled (wrapping) in both directions, with its mean R̂ (Eq. 7);
/// and the Gaussian form of its colours, in which the histogram-preserving
/// blend works (GaussianExemplar, blend.h).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "fluidtex/geometry/image.h"
#include "fluidtex/geometry/mesh.h"

namespace fluidtex {

class GaussianExemplar;

class Exemplar {
 public:
  /// `image` must have 1 to 4 channels; only the first three (or one) are
  /// used as colour.
  explicit Exemplar(Image image);
  /// Reads through OpenImageIO (see image_io.h for how sRGB is treated).
  static Exemplar load(const std::string& path);

  int channels() const { return channels_; }  ///< 1 (grey) or 3 (RGB)
  const std::array<float, 3>& mean() const { return mean_; }
  const std::array<float, 3>& stddev() const { return stddev_; }
  const Image& image() const { return image_; }

  /// Bilinear, wrapping lookup at tile coordinates (u right, v up; one tile
  /// per unit). Writes channels() values.
  void sample(double u, double v, float* out) const;

  /// The exemplar's Gaussian form (GaussianExemplar), made on first use and
  /// shared by copies of this exemplar. Thread safe.
  const GaussianExemplar& gaussian() const;

 private:
  struct Lazy;
  std::shared_ptr<Lazy> lazy_;
  Image image_;
  int channels_ = 3;
  std::array<float, 3> mean_{0, 0, 0};
  std::array<float, 3> stddev_{0, 0, 0};
};

/// The space where the histogram-preserving blend works (Heitz and Neyret
/// 2018, Sec. 3.2 and 4): colours minus the exemplar's mean, in the
/// principal axes of its colours' covariance (one channel: as it is), each
/// axis mapped through the exemplar's CDF along it to a standard normal
/// variable G. The CDF is the empirical one, piecewise linear between the
/// axis's distinct values at their mean ranks, so that equal texels share a
/// value and the map is invertible; both directions are tables over the
/// axis's range and over G ∈ [−kRange, kRange], linear in between. A sample
/// is mapped after its bilinear lookup, so one patch alone shows exactly
/// what the other blends show. Built once per exemplar (Exemplar::gaussian).
class GaussianExemplar {
 public:
  explicit GaussianExemplar(const Exemplar& exemplar);

  /// G of a colour (`channels` values of the exemplar's channels).
  void to_gaussian(const float* colour, double* g) const;
  /// The colour of G: the inverse of to_gaussian up to the tables'
  /// resolution (values beyond the axis's range clamp to its ends).
  void to_colour(const double* g, float* out) const;

  static constexpr double kRange = 6.0;

 private:
  /// A function tabulated at points spread evenly from `origin`, `step`
  /// apart; linear in between, its end values beyond.
  struct Table {
    double origin = 0.0, per_step = 0.0;  ///< per_step: 1 / step (0: a constant)
    std::vector<float> values;
    double at(double x) const;
  };
  /// One principal axis: its direction and the two tables.
  struct Axis {
    std::array<double, 3> direction{};
    Table forward;  ///< G of the values along it, over their range
    Table inverse;  ///< the value of G, over [−kRange, kRange]
  };
  int channels_ = 3;
  std::array<double, 3> mean_{};
  std::array<Axis, 3> axes_;
};

}  // namespace fluidtex
