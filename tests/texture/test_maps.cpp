// Tests of the height and normal atlases (texture/maps.h) on hand-made
// charts, where the slopes are known.
#include <gtest/gtest.h>

#include <cmath>

#include "fluidtex/texture/maps.h"

namespace fluidtex {
namespace {

/// An n x n atlas whose left half (x < n/2) is chart 0 and right half chart
/// 1, `density` texels per scene unit; the rest of the map points at faces
/// 0 and 1.
struct TwoCharts {
  int n = 16;
  Atlas atlas;
  TexelMap map;
  explicit TwoCharts(double density) {
    atlas.size = n;
    atlas.texels_per_unit = density;
    atlas.face_chart = {0, 1};
    map.size = n;
    map.face.assign(std::size_t(n) * n, -1);
    for (int y = 1; y < n - 1; ++y) {
      for (int x = 1; x < n - 1; ++x) map.face[texel_index(x, y, n)] = x < n / 2 ? 0 : 1;
    }
  }
};

Vec3 decoded(const Image& normal, int x, int y) {
  return Vec3(2.0 * normal.at(x, y, 0) - 1.0, 2.0 * normal.at(x, y, 1) - 1.0, 2.0 * normal.at(x, y, 2) - 1.0);
}

TEST(SurfaceMaps, HeightIsTheColoursLuminance) {
  Image color = Image::blank(2, 1, 3);
  color.at(0, 0, 0) = 1.0f;
  color.at(1, 0, 1) = 0.5f, color.at(1, 0, 2) = 1.0f;
  const Image height = height_map(color);
  ASSERT_EQ(height.channels, 1);
  EXPECT_FLOAT_EQ(height.at(0, 0, 0), 0.2126f);
  EXPECT_FLOAT_EQ(height.at(1, 0, 0), 0.7152f * 0.5f + 0.0722f);
}

TEST(SurfaceMaps, NormalsFollowTheSlopeInTheUvFrame) {
  const double density = 40.0, bump = 0.01;
  TwoCharts charts(density);
  const int n = charts.n;
  // Height rising by 0.05 per texel to the right (+u) in chart 0, by 0.02
  // per texel downwards (−v) in chart 1, and a jump of 1 between the charts.
  Image height = Image::blank(n, n, 1);
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) height.at(x, y, 0) = x < n / 2 ? 0.05f * x : 1.0f + 0.02f * y;
  }
  const Image normal = normal_map(height, charts.map, charts.atlas, bump);
  ASSERT_EQ(normal.channels, 3);
  // Scene slope: bump · density · (height step per texel).
  const double su = bump * density * 0.05, sv = -bump * density * 0.02;
  const Vec3 expected_left = Vec3(-su, 0.0, 1.0).normalized(), expected_right = Vec3(0.0, -sv, 1.0).normalized();
  for (int y = 1; y < n - 1; ++y) {
    for (int x = 1; x < n - 1; ++x) {
      const Vec3 got = decoded(normal, x, y);
      // The jump between the charts never shows: each side differences
      // within its own chart (one-sided at the border).
      EXPECT_LT((got - (x < n / 2 ? expected_left : expected_right)).norm(), 1e-5) << x << "," << y;
    }
  }
  // Outside the charts: dilated from the neighbouring chart texels, unit length.
  EXPECT_NEAR(decoded(normal, 0, 5).norm(), 1.0, 1e-3);
  EXPECT_LT((decoded(normal, 0, 5) - expected_left).norm(), 1e-5);
}

TEST(SurfaceMaps, FlatHeightGivesTheFlatNormal) {
  TwoCharts charts(10.0);
  Image height = Image::blank(charts.n, charts.n, 1);
  for (float& h : height.pixels) h = 0.3f;
  const Image normal = normal_map(height, charts.map, charts.atlas, 5.0);
  for (std::size_t i = 0; i < normal.pixels.size(); i += 3) {
    EXPECT_FLOAT_EQ(normal.pixels[i], 0.5f);
    EXPECT_FLOAT_EQ(normal.pixels[i + 1], 0.5f);
    EXPECT_FLOAT_EQ(normal.pixels[i + 2], 1.0f);
  }
}

}  // namespace
}  // namespace fluidtex
