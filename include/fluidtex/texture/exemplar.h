/// @file exemplar.h
/// @brief The exemplar texture as the synthesis samples it: linear float,
/// bilinear, tiled (wrapping) in both directions, with its mean R̂ (Eq. 7).
#pragma once

#include <array>
#include <string>

#include "fluidtex/geometry/image.h"
#include "fluidtex/geometry/mesh.h"

namespace fluidtex {

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

 private:
  Image image_;
  int channels_ = 3;
  std::array<float, 3> mean_{0, 0, 0};
  std::array<float, 3> stddev_{0, 0, 0};
};

}  // namespace fluidtex
