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

const Image* TiledAtlas::tile_at(Vec2& uv) const {
  if (!udim) {
    uv = uv.cwiseMax(0.0).cwiseMin(1.0);
    return &tiles.front();
  }
  const double column = std::floor(uv.x()), row = std::floor(uv.y());
  if (!(column >= 0.0 && column < 10.0 && row >= 0.0 && row < 900.0)) return nullptr;
  const int number = 1001 + static_cast<int>(column) + 10 * static_cast<int>(row);
  const auto it = std::lower_bound(udims.begin(), udims.end(), number);
  if (it == udims.end() || *it != number) return nullptr;
  uv -= Vec2(column, row);
  return &tiles[static_cast<std::size_t>(it - udims.begin())];
}

void TiledAtlas::sample(Vec2 uv, float* out, int channels) const {
  const Image* tile = tile_at(uv);
  if (!tile) {
    for (int c = 0; c < (channels > 0 ? channels : first().channels); ++c) out[c] = 0.0f;
    return;
  }
  sample_bilinear(*tile, u_to_px(uv.x(), tile->width), v_to_py(uv.y(), tile->height), out, channels);
}

}  // namespace fluidtex
