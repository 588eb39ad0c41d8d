/// @file exemplar.h
/// @brief The exemplar texture as the synthesis samples it: linear float,
/// bilinear, tiled (wrapping) in both directions, with its mean R̂ (Eq. 7);
/// and its Gaussian form, which the histogram-preserving blend samples
/// (GaussianExemplar, blend.h).
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

/// The exemplar in the space where the histogram-preserving blend works
/// (Heitz and Neyret 2018, Sec. 3.2 and 4): colours minus their mean, in the
/// principal axes of their covariance (one channel: as they are), each axis
/// mapped through its empirical CDF to a standard normal variable. Texels of
/// equal value share their mean rank, so an 8-bit exemplar's flat areas
/// stay flat. Built once per exemplar (Exemplar::gaussian).
class GaussianExemplar {
 public:
  explicit GaussianExemplar(const Exemplar& exemplar);

  /// The Gaussianised exemplar, sampled as the exemplar is (tiled, bilinear).
  const Exemplar& image() const { return *image_; }
  /// A colour from a point G of the Gaussian space: per axis the inverse
  /// CDF (a table over G ∈ [−kRange, kRange], linear in between; beyond, the
  /// axis's extreme value), then back to colour. Writes `channels` values.
  void to_colour(const double* g, float* out) const;

  static constexpr double kRange = 6.0;

 private:
  std::unique_ptr<Exemplar> image_;
  int channels_ = 3;
  std::array<double, 3> mean_{};
  std::array<std::array<double, 3>, 3> axes_{};  ///< axes_[k]: the k-th principal axis (unit)
  std::array<std::vector<float>, 3> inverse_;    ///< per axis: value at G on a uniform grid
};

}  // namespace fluidtex
