// Blending (texture/blend.h): the Gaussian form of an exemplar and its
// inverse, the histogram-preserving blend against Eq. 7 on a structured
// exemplar, and weight sharpening.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "fluidtex/texture/blend.h"
#include "fluidtex/texture/synthesis.h"
#include "fluidtex/util/random.h"
#include "synthesis_fixtures.h"

namespace fluidtex {
namespace {

/// Bricks: 0.85 courses of 16 × 8 texels (offset every other course)
/// with 0.15 mortar lines, a little deterministic grain: a strongly bimodal,
/// structured exemplar (64², grey or RGB).
Exemplar bricks(int channels) {
  Image image = Image::blank(64, 64, channels);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      const int shift = (y / 8) % 2 ? 8 : 0;
      const bool mortar = y % 8 == 0 || (x + shift) % 16 == 0;
      const double grain = 0.05 * (uniform(7, Stream::PatchAnchor, static_cast<std::uint64_t>(x), y) - 0.5);
      for (int c = 0; c < channels; ++c)
        image.at(x, y, c) = static_cast<float>((mortar ? 0.15 : 0.85 - 0.2 * c) + grain);
    }
  }
  return Exemplar(std::move(image));
}

/// 1-D Wasserstein distance between two samples of equal size.
double wasserstein(std::vector<double> a, std::vector<double> b) {
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += std::abs(a[i] - b[i]);
  return sum / static_cast<double>(a.size());
}

TEST(GaussianExemplar, MapsBackToTheExemplarsColours) {
  for (int channels : {1, 3}) {
    const Exemplar exemplar = bricks(channels);
    const GaussianExemplar& g = exemplar.gaussian();
    EXPECT_EQ(&g, &exemplar.gaussian());  // made once
    // The texels' G are standard normal along every axis, and map back to
    // the texels, but for the few whose G falls in the inverse table's step
    // across the gap between mortar and brick values (interpolated there).
    std::array<double, 3> sum{}, sum2{};
    std::size_t off = 0;
    for (std::size_t i = 0; i < 64 * 64; ++i) {
      const float* texel = exemplar.image().pixel(i);
      double at[3];
      g.to_gaussian(texel, at);
      float back[3];
      g.to_colour(at, back);
      double error = 0.0;
      for (int c = 0; c < channels; ++c) {
        sum[c] += at[c], sum2[c] += at[c] * at[c];
        error = std::max(error, std::abs(double(back[c]) - texel[c]));
      }
      off += error > 2e-3;
    }
    for (int c = 0; c < channels; ++c) {
      EXPECT_NEAR(sum[c] / 4096, 0.0, 0.01) << c;
      EXPECT_NEAR(std::sqrt(sum2[c] / 4096), 1.0, 0.05) << c;
    }
    EXPECT_LE(off, 8u) << channels;
  }
}

/// A texel centre of the 64² exemplar picked by (i, k): where a bilinear
/// lookup is that texel.
double texel_centre(int i, std::uint64_t k, int axis) {
  return (std::floor(64.0 * uniform(3, Stream::PatchAnchor, i, k, axis)) + 0.5) / 64.0;
}

/// The green values of `n` texels that blend two texels of the exemplar at
/// unrelated places with equal weights, under `blend`.
std::vector<double> two_sample_blend(const Exemplar& exemplar, Blend blend, int n) {
  const Blender blender(exemplar, blend);
  std::vector<double> out;
  for (int i = 0; i < n; ++i) {
    double sum[3] = {0, 0, 0};
    for (std::uint64_t k = 0; k < 2; ++k) {
      double term[3];
      blender.sample(texel_centre(i, k, 0), texel_centre(i, k, 1), term);
      for (int c = 0; c < 3; ++c) sum[c] += 0.5 * term[c];
    }
    float texel[3];
    blender.resolve(sum, 1.0, 0.5, texel);
    out.push_back(texel[1]);
  }
  return out;
}

TEST(Blend, HistogramKeepsAStructuredExemplarsHistogram) {
  const Exemplar exemplar = bricks(3);
  const int n = 4096;
  // What one patch shows: texels of the exemplar.
  std::vector<double> reference;
  for (int i = 0; i < n; ++i) {
    float r[3];
    exemplar.sample(texel_centre(i, 2, 0), texel_centre(i, 2, 1), r);
    reference.push_back(r[1]);
  }
  const double sd = exemplar.stddev()[1];
  const double histogram = wasserstein(two_sample_blend(exemplar, Blend::Histogram, n), reference) / sd;
  const double contrast = wasserstein(two_sample_blend(exemplar, Blend::ContrastPreserving, n), reference) / sd;
  const double linear = wasserstein(two_sample_blend(exemplar, Blend::Linear, n), reference) / sd;
  // Eq. 7 makes a third mode between bricks and mortar and pushes the
  // others out of range; the linear blend turns them into that third mode.
  EXPECT_LT(histogram, 0.06);
  EXPECT_GT(contrast, 0.15);
  EXPECT_GT(linear, 0.3);
}

TEST(Blend, OneSampleIsTheExemplar) {
  const Exemplar exemplar = bricks(3);
  for (Blend blend : {Blend::ContrastPreserving, Blend::Linear, Blend::Histogram}) {
    const Blender blender(exemplar, blend);
    for (int x : {3, 17, 40, 63}) {  // texel centres, where bilinear lookups are the texel
      const double u = (x + 0.5) / 64.0, v = (63 - x + 0.5) / 64.0;
      double term[3];
      float texel[3], expect[3];
      blender.sample(u, v, term);
      EXPECT_FALSE(blender.resolve(term, 1.0, 1.0, texel));
      exemplar.sample(u, v, expect);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(texel[c], expect[c], blend == Blend::Histogram ? 0.02 : 1e-6);
    }
  }
}

TEST(Blend, SharpeningLeavesTheLargestAndLowersTheRest) {
  EXPECT_EQ(sharpened(0.3, 0.8, 1.0), 0.3);
  EXPECT_DOUBLE_EQ(sharpened(0.8, 0.8, 4.0), 0.8);
  EXPECT_DOUBLE_EQ(sharpened(0.4, 0.8, 4.0), 0.8 / 16.0);
  EXPECT_EQ(sharpened(0.0, 0.8, 4.0), 0.0);
}

TEST(Blend, SharpenedTexelsShowOnePatch) {
  test::OnePatch scene(64);
  scene.add(Vec2(0.25, 0.5), 1.0);
  scene.add(Vec2(0.6, 0.1), 0.5).kt = 0.5;  // its core weight: K_t
  const Exemplar exemplar = bricks(3);
  SynthesisOptions so;
  so.tile_size = 1.0;
  so.radius = 1e3;  // the fixture's weights: core ≈ w everywhere
  const SynthesisResult flat = synthesize(scene.surface, scene.atlas, scene.map, scene.patches, exemplar, so);
  so.sharpness = 8.0;  // 0.5⁸: the second patch keeps 0.4 % of the weight
  const SynthesisResult sharp = synthesize(scene.surface, scene.atlas, scene.map, scene.patches, exemplar, so);
  ASSERT_GT(flat.chart_texels, 1000u);
  EXPECT_EQ(flat.dominant_texels, 0u);  // 1 of 1.5
  EXPECT_EQ(sharp.dominant_texels, sharp.chart_texels);
}

}  // namespace
}  // namespace fluidtex
