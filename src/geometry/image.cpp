#include "fluidtex/geometry/image.h"

namespace fluidtex {

void sample_bilinear(const Image& image, double x, double y, float* out, int channels) {
  const int w = image.width, h = image.height, nc = image.channels;
  const double fx = std::clamp(x - 0.5, 0.0, static_cast<double>(w - 1));
  const double fy = std::clamp(y - 0.5, 0.0, static_cast<double>(h - 1));
  const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
  const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
  const double ax = fx - x0, ay = fy - y0;
  auto at = [&](int xx, int yy, int c) {
    return static_cast<double>(image.pixels[(static_cast<std::size_t>(yy) * w + xx) * nc + c]);
  };
  for (int c = 0; c < (channels > 0 ? std::min(channels, nc) : nc); ++c) {
    out[c] = static_cast<float>((1 - ay) * ((1 - ax) * at(x0, y0, c) + ax * at(x1, y0, c)) +
                                ay * ((1 - ax) * at(x0, y1, c) + ax * at(x1, y1, c)));
  }
}

}  // namespace fluidtex
