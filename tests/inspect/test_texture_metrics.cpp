// What an atlas looks like against its exemplar: contrast, spectrum, the
// chart texels and the texel density, each on a case with a known answer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "fluidtex/inspect/texture_metrics.h"
#include "fluidtex/scenes/exemplar_gen.h"
#include "fluidtex/texture/atlas.h"
#include "fluidtex/texture/synthesis.h"
#include "fluidtex/util/error.h"
#include "mesh_fixtures.h"
#include "synthesis_fixtures.h"

namespace fluidtex {
namespace {

TEST(TextureMetrics, ContrastRatioIsOneForASinglePatch) {
  // One patch of weight 1 over the unit square showing exactly 4×4 tiles.
  // A smooth exemplar, so that bilinear lookups between its texels do not
  // lower the contrast themselves.
  Image smooth;
  smooth.width = smooth.height = 64;
  smooth.channels = 3;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      smooth.pixels.push_back(static_cast<float>(0.5 + 0.3 * std::sin(2 * M_PI * x / 64.0)));
      smooth.pixels.push_back(static_cast<float>(0.5 + 0.2 * std::cos(2 * M_PI * y / 32.0)));
      smooth.pixels.push_back(static_cast<float>(0.5 + 0.25 * std::sin(2 * M_PI * (x + y) / 64.0)));
    }
  }
  test::OnePatch scene(256);
  scene.add(Vec2(0.1, 0.3), 1.0);
  const Exemplar exemplar(smooth);
  SynthesisOptions so;
  so.tile_size = 0.25;
  so.radius = 1e3;
  const SynthesisResult r = synthesize(scene.surface, scene.atlas, scene.map, scene.patches, exemplar, so);
  std::vector<char> mask(scene.map.face.size());
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = scene.map.face[i] >= 0;
  for (double ratio : contrast_ratio(r.color, mask, exemplar, 1.0)) EXPECT_NEAR(ratio, 1.0, 0.03);
  // Linear blending of four uncorrelated patches loses contrast.
  test::OnePatch four(256);
  for (int k = 0; k < 4; ++k) four.add(Vec2(0.13 * k + 0.05, 0.29 * k + 0.1), 1.0, 0.9 * k);
  so.blend = Blend::Linear;
  const SynthesisResult lin = synthesize(four.surface, four.atlas, four.map, four.patches, exemplar, so);
  for (double ratio : contrast_ratio(lin.color, mask, exemplar, 1.0)) EXPECT_LT(ratio, 0.75);
}

TEST(TextureMetrics, ContrastIsMeasuredAgainstTheExemplarAtTheAtlasScale) {
  // The exemplar magnified 4× (bilinear) is smoother than the exemplar:
  // against its own σ it looks washed out, against its σ at that scale not.
  const Exemplar exemplar(make_exemplar("gravel", 64, 8));
  const Image magnified = exemplar_crop(exemplar, 3.3, 1.7, 0.25, 256);
  const std::vector<char> mask(256 * 256, 1);
  const std::vector<double> at_scale = contrast_ratio(magnified, mask, exemplar, 0.25);
  const std::vector<double> sigma = resampled_stddev(exemplar, 0.25);
  ASSERT_EQ(at_scale.size(), 3u);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(at_scale[c], 1.0, 0.05) << c;
    EXPECT_LT(sigma[c], 0.95 * exemplar.stddev()[c]) << c;
  }
}

TEST(TextureMetrics, SpectrumDistanceIsZeroForTheExemplarItself) {
  const Exemplar exemplar(make_exemplar("gravel", 128, 8));
  const std::vector<double> s = radial_log_spectrum(exemplar.image(), 0, 0, 64);
  ASSERT_EQ(s.size(), 31u);
  EXPECT_DOUBLE_EQ(spectrum_distance(s, s), 0.0);
  // The same texture resampled at scale 1 is the same spectrum; a blurred
  // one (half resolution) is not.
  const Image same = exemplar_crop(exemplar, 0.0, 0.0, 1.0, 64);
  EXPECT_LT(spectrum_distance(radial_log_spectrum(same, 0, 0, 64), s), 1e-6);
  const Image zoomed = exemplar_crop(exemplar, 0.0, 0.0, 0.5, 64);
  EXPECT_GT(spectrum_distance(radial_log_spectrum(zoomed, 0, 0, 64), s), 0.5);
  EXPECT_THROW(radial_log_spectrum(exemplar.image(), 100, 0, 64), InternalError);
}

TEST(TextureMetrics, ChartMaskCoversTheUvTriangles) {
  const UVMesh m = test::textured_grid(4, 0.0);  // the whole [0,1]² in uv
  const std::vector<char> mask = chart_mask(m, 32);
  EXPECT_EQ(std::count(mask.begin(), mask.end(), 1), 32 * 32);
  UVMesh half = m;
  for (Vec2& uv : half.uvs) uv *= 0.5;  // lower-left quarter in uv = bottom-left in the image (y down)
  const std::vector<char> q = chart_mask(half, 32);
  EXPECT_EQ(std::count(q.begin(), q.end(), 1), 16 * 16);
  EXPECT_TRUE(q[31 * 32 + 0]);
  EXPECT_FALSE(q[0]);
}

TEST(TextureMetrics, TexelDensityIsTexelsPerSceneUnit) {
  // The unit square filling a 64² atlas: 64 texels per unit; the same uvs
  // on a square twice as large: 32.
  UVMesh m = test::textured_grid(4, 0.0);
  EXPECT_NEAR(texel_density(m, 64), 64.0, 1e-9);
  for (Vec3& p : m.positions) p *= 2.0;
  EXPECT_NEAR(texel_density(m, 64), 32.0, 1e-9);
  // Half the uv range in each direction: a quarter of the texels.
  for (Vec2& uv : m.uvs) uv *= 0.5;
  EXPECT_NEAR(texel_density(m, 64), 16.0, 1e-9);
  EXPECT_EQ(texel_density(UVMesh{}, 64), 0.0);
}

TEST(TextureMetrics, ChartWindowsLieInsideTheCharts) {
  // The left half of a 64² atlas is chart: 16² windows at half steps.
  std::vector<char> mask(64 * 64, 0);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 32; ++x) mask[y * 64 + x] = 1;
  const auto all = chart_windows(mask, 64, 16, 1000);
  EXPECT_EQ(all.size(), 3u * 7u);  // x in {0, 8, 16}, y in {0, 8, ..., 48}
  for (const auto& [x, y] : all) EXPECT_LE(x + 16, 32);
  const auto few = chart_windows(mask, 64, 16, 5);
  ASSERT_EQ(few.size(), 5u);
  EXPECT_EQ(few, chart_windows(mask, 64, 16, 5));
}

TEST(TextureMetrics, TheExemplarSpanIsMeasuredFromTheAtlasThroughTheUvMesh) {
  // The unit square shows the exemplar at a known tile size, by one patch
  // and by four rotated patches blended (Eq. 7); the measure finds the tile
  // size from the atlas and the UV mesh alone, from a guess 1.6 times off.
  const Exemplar exemplar(make_exemplar("gravel", 128, 3));
  for (const double tile : {0.2, 0.45}) {
    for (const int patches : {1, 4}) {
      SCOPED_TRACE("tile " + std::to_string(tile) + ", " + std::to_string(patches) + " patches");
      test::OnePatch scene(512);
      for (int k = 0; k < patches; ++k) scene.add(Vec2(0.13 * k + 0.05, 0.29 * k + 0.1), 1.0, 0.9 * k);
      SynthesisOptions so;
      so.tile_size = tile;
      so.radius = 1e3;
      const SynthesisResult r = synthesize(scene.surface, scene.atlas, scene.map, scene.patches, exemplar, so);
      const UVMesh mesh = atlas_uv_mesh(scene.surface, scene.atlas);
      EXPECT_NEAR(measured_exemplar_span(r.color, mesh, exemplar, 1.6 * tile) / tile, 1.0, 0.08);
      EXPECT_NEAR(measured_exemplar_span(r.color, mesh, exemplar, tile / 1.6) / tile, 1.0, 0.08);
    }
  }
  EXPECT_TRUE(std::isnan(measured_exemplar_span(Image::blank(64, 64, 3), UVMesh{}, exemplar, 0.3)));
}

}  // namespace
}  // namespace fluidtex
