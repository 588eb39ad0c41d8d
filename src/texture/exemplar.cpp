#include "fluidtex/texture/exemplar.h"

#include <cmath>

#include "fluidtex/io/image_io.h"
#include "fluidtex/util/error.h"

namespace fluidtex {

Exemplar::Exemplar(Image image) : image_(std::move(image)) {
  if (image_.width < 1 || image_.height < 1 || image_.channels < 1) throw InputError("", "empty exemplar image");
  channels_ = image_.channels >= 3 ? 3 : 1;
  const std::size_t n = static_cast<std::size_t>(image_.width) * image_.height;
  for (int c = 0; c < channels_; ++c) {
    double sum = 0.0, sum2 = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double v = image_.pixels[i * image_.channels + c];
      sum += v;
      sum2 += v * v;
    }
    const double mean = sum / static_cast<double>(n);
    mean_[c] = static_cast<float>(mean);
    stddev_[c] = static_cast<float>(std::sqrt(std::max(0.0, sum2 / static_cast<double>(n) - mean * mean)));
  }
}

Exemplar Exemplar::load(const std::string& path) {
  Image image = read_image(path);
  if (image.channels == 2) throw InputError(path, "exemplar has 2 channels (expected grey, RGB or RGBA)");
  for (float v : image.pixels) {
    if (!std::isfinite(v)) throw InputError(path, "exemplar has NaN or infinite pixels");
  }
  try {
    return Exemplar(std::move(image));
  } catch (const InputError& e) {
    throw InputError(path, e.problem());
  }
}

void Exemplar::sample(double u, double v, float* out) const {
  const int w = image_.width, h = image_.height;
  // Texel centres at (i + ½)/w; v up, rows down.
  const double x = u_to_px(u, w) - 0.5;
  const double y = v_to_py(v, h) - 0.5;
  double fx = std::floor(x), fy = std::floor(y);
  if (!std::isfinite(fx) || !std::isfinite(fy)) fx = fy = 0.0;  // cannot come from a finite uv of a sane scale
  // Far from the origin, wrap before converting to an integer (exact for
  // integers below 2^53; farther out only the precision of the lookup suffers).
  if (std::abs(fx) > 0x1p30) fx -= w * std::floor(fx / w);
  if (std::abs(fy) > 0x1p30) fy -= h * std::floor(fy / h);
  const double tx = x - fx, ty = y - fy;
  // |fx|, |fy| <= 2^30 here: int arithmetic (a 32-bit division is the
  // cheaper one).
  auto wrap = [](int i, int n) {
    const int r = i % n;
    return r < 0 ? r + n : r;
  };
  const int x0 = wrap(static_cast<int>(fx), w), x1 = x0 + 1 == w ? 0 : x0 + 1;
  const int y0 = wrap(static_cast<int>(fy), h), y1 = y0 + 1 == h ? 0 : y0 + 1;
  const float* p00 = image_.pixel(texel_index(x0, y0, w));
  const float* p10 = image_.pixel(texel_index(x1, y0, w));
  const float* p01 = image_.pixel(texel_index(x0, y1, w));
  const float* p11 = image_.pixel(texel_index(x1, y1, w));
  const float a = static_cast<float>((1 - tx) * (1 - ty)), b = static_cast<float>(tx * (1 - ty));
  const float c = static_cast<float>((1 - tx) * ty), d = static_cast<float>(tx * ty);
  for (int k = 0; k < channels_; ++k) out[k] = a * p00[k] + b * p10[k] + c * p01[k] + d * p11[k];
}

}  // namespace fluidtex
