#include "fluidtex/texture/maps.h"

#include <cmath>

#include <tbb/parallel_for.h>

namespace fluidtex {

Image height_map(const Image& color) {
  if (color.channels == 1) return color;
  Image height = Image::blank(color.width, color.height, 1);
  for (std::size_t i = 0; i < height.pixels.size(); ++i) height.pixels[i] = luminance_at<float>(color, i);
  return height;
}

Image normal_map(const Image& height, const TexelMap& map, const Atlas& atlas, double bump_height) {
  const int n = height.width;
  Image normal = Image::blank(n, height.height, 3);
  std::vector<char> mask(map.face.size(), 0);
  // A height step of 1 across one texel is a slope of bump_height · density.
  const double scale = bump_height * atlas.texels_per_unit;
  auto chart_of = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= n || y >= height.height) return -1;
    const int face = map.face[texel_index(x, y, n)];
    return face < 0 ? -1 : atlas.face_chart[face];
  };
  // d height / d step along (dx, dy), within chart `chart`.
  auto slope = [&](int x, int y, int dx, int dy, int chart) {
    const bool ahead = chart_of(x + dx, y + dy) == chart, behind = chart_of(x - dx, y - dy) == chart;
    const double here = height.at(x, y, 0);
    if (ahead && behind) return 0.5 * (height.at(x + dx, y + dy, 0) - height.at(x - dx, y - dy, 0));
    if (ahead) return height.at(x + dx, y + dy, 0) - here;
    if (behind) return here - height.at(x - dx, y - dy, 0);
    return 0.0;
  };
  tbb::parallel_for(0, height.height, [&](int y) {
    for (int x = 0; x < n; ++x) {
      const int chart = chart_of(x, y);
      if (chart < 0) continue;
      // x right is +u; y down is −v.
      const double su = scale * slope(x, y, 1, 0, chart);
      const double sv = -scale * slope(x, y, 0, 1, chart);
      const double length = std::sqrt(su * su + sv * sv + 1.0);
      float* p = normal.pixel(texel_index(x, y, n));
      p[0] = static_cast<float>(0.5 - 0.5 * su / length);
      p[1] = static_cast<float>(0.5 - 0.5 * sv / length);
      p[2] = static_cast<float>(0.5 + 0.5 / length);
      mask[texel_index(x, y, n)] = 1;
    }
  });
  const std::vector<char> in_chart = mask;
  dilate(normal, mask, 8);
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (in_chart[i]) continue;
    float* p = normal.pixel(i);
    if (!mask[i]) {
      p[0] = p[1] = 0.5f, p[2] = 1.0f;  // beyond the dilated gutter: the flat normal
      continue;
    }
    // A gutter texel holds a mean of unit normals: unit length again.
    const Vec3 unit = Vec3(2.0 * p[0] - 1.0, 2.0 * p[1] - 1.0, 2.0 * p[2] - 1.0).normalized();
    for (int c = 0; c < 3; ++c) p[c] = static_cast<float>(0.5 + 0.5 * unit[c]);
  }
  return normal;
}

}  // namespace fluidtex
