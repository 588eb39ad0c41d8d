// How much an atlas still looks like its exemplar: orientation, nearest-
// window energy, colour distribution and the autocorrelation at the patch
// spacing, each on procedural images with a known answer (stripes at known
// angles, bricks, noise, blends of copies, blobs on a lattice).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <oneapi/tbb/task_arena.h>

#include "fluidtex/inspect/appearance_metrics.h"
#include "fluidtex/inspect/texture_metrics.h"
#include "fluidtex/inspect/textured_frame.h"
#include "fluidtex/scenes/exemplar_gen.h"
#include "mesh_fixtures.h"

namespace fluidtex {
namespace {

constexpr double kDeg = M_PI / 180.0;

/// Periodic RGB stripes on a size² tile: kx and ky cycles across it along
/// x and y (y up, as seen); the stripes run at atan2(ky, kx) + 90°.
Image stripes(int size, int kx, int ky) {
  Image image = Image::blank(size, size, 3);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const double phase = 2.0 * M_PI * (kx * (x + 0.5) + ky * (size - y - 0.5)) / size;
      const float v = static_cast<float>(0.5 + 0.35 * std::sin(phase));
      image.at(x, y, 0) = v, image.at(x, y, 1) = 0.8f * v, image.at(x, y, 2) = 0.6f * v + 0.1f;
    }
  }
  return image;
}

/// The direction stripes(·, kx, ky) run in, radians in [0, π).
double stripe_direction(int kx, int ky) { return std::fmod(std::atan2(ky, kx) + 0.5 * M_PI + M_PI, M_PI); }

/// Running bond bricks on a 64² tile: 16×8 bricks, rows offset by half a
/// brick, soft mortar lines about 3 texels wide, a grain on each brick.
Image bricks() {
  Image image = Image::blank(64, 64, 3);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      const int row = y / 8, bx = (x + (row % 2) * 8) % 16;
      const int d = std::min({y % 8, 8 - y % 8, bx, 16 - bx});  // texels to the nearest mortar line
      const double mortar = std::max(0.0, 1.0 - d / 2.0);
      const double grain = 0.05 * std::sin(1.7 * x + 2.3 * y);
      const float v = static_cast<float>(0.35 + grain + (0.85 - 0.35 - grain) * mortar);
      image.at(x, y, 0) = v, image.at(x, y, 1) = 0.7f * v, image.at(x, y, 2) = 0.5f * v;
    }
  }
  return image;
}

/// A checkerboard of 16-texel squares on a 64² tile, 0.2 and 0.8.
Image checker() {
  Image image = Image::blank(64, 64, 3);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = (x / 16 + y / 16) % 2 ? 0.8f : 0.2f;
    }
  }
  return image;
}

/// The unit square in the plane z = 0, its uvs its x and y: an atlas whose
/// texels read on the surface as they are drawn.
UVMesh square() { return test::textured_grid(4, 0.0); }

/// The unit square of uv laid on the plane z = 0 by `m` (position = m·uv):
/// a chart turned (and mirrored where det m < 0) against the surface.
UVMesh chart(const Eigen::Matrix2d& m) {
  UVMesh mesh = square();
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const Vec2 p = m * mesh.uvs[i];
    mesh.positions[i] = Vec3(p.x(), p.y(), 0.0);
  }
  return mesh;
}

/// A size² atlas of chart(m) showing `exemplar` projected onto the plane
/// (uv = (x, y) / tile + shift, a flow map at rest): the exemplar unturned
/// on the surface, however the chart turns.
Image projected(const Exemplar& exemplar, const Eigen::Matrix2d& m, double tile, int size,
                const Vec2& shift = Vec2::Zero()) {
  Image image = Image::blank(size, size, exemplar.channels());
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const Vec2 q = m * Vec2(px_to_u(x + 0.5, size), py_to_v(y + 0.5, size)) / tile + shift;
      exemplar.sample(q.x(), q.y(), image.pixel(texel_index(x, y, size)));
    }
  }
  return image;
}

std::vector<char> everywhere(const Image& image) {
  return std::vector<char>(static_cast<std::size_t>(image.width) * image.height, 1);
}

/// The mean of two images of one size.
Image average(const Image& a, const Image& b) {
  Image out = a;
  for (std::size_t i = 0; i < out.pixels.size(); ++i) out.pixels[i] = 0.5f * (a.pixels[i] + b.pixels[i]);
  return out;
}

/// `image` turned by 90° (a transposed and mirrored copy).
Image turned(const Image& image) {
  Image out = Image::blank(image.height, image.width, image.channels);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      for (int c = 0; c < image.channels; ++c) out.at(y, image.width - 1 - x, c) = image.at(x, y, c);
    }
  }
  return out;
}

TEST(AppearanceMetrics, StripesPointAlongTheirDirection) {
  // Stripes at 29.7° (4 and 7 cycles across a 64² tile), tiled over 256².
  const Exemplar at30(stripes(64, -4, 7));
  const Image atlas = exemplar_crop(at30, 5.3, 2.1, 1.0, 256);
  const auto windows = chart_windows(everywhere(atlas), 256, 64, 64);
  const TextureOrientation o = texture_orientation(atlas, windows, 64);
  EXPECT_GT(o.coherence, 0.95);
  EXPECT_NEAR(dominant_direction(o), stripe_direction(-4, 7), 1.0 * kDeg);
  const std::vector<double> h = direction_histogram(o);
  EXPECT_NEAR(h[2], 1.0, 1e-9);  // 30°: the bin of 22.5° .. 37.5°
  EXPECT_NEAR(direction_histogram(o, 12, dominant_direction(o))[0], 1.0, 1e-9);
  // A flat image has no direction.
  const Image flat = Image::blank(64, 64, 3);
  EXPECT_TRUE(std::isnan(dominant_direction(texture_orientation(flat, {{0, 0}}, 64))));
}

TEST(AppearanceMetrics, OrientationAgainstTheExemplarIsRotationAware) {
  const Exemplar at30(stripes(64, -4, 7)), at75(stripes(64, -7, 2));
  const Image atlas = exemplar_crop(at30, 5.3, 2.1, 1.0, 256);
  const std::vector<char> mask = everywhere(atlas);
  // The same stripes: the same coherence and direction.
  const OrientationFigures same = orientation_figures(atlas, square(), mask, at30, 1.0);
  EXPECT_EQ(same.window, 64);
  EXPECT_NEAR(same.coherence_ratio, 1.0, 0.02);
  EXPECT_LT(same.angle_deg, 3.0);
  EXPECT_LT(same.histogram_distance, 0.05);
  EXPECT_LT(same.aligned_histogram_distance, 0.05);
  // Stripes at 74.1°: turned by 44.3°, as coherent, and the same up to the turn.
  const OrientationFigures other = orientation_figures(atlas, square(), mask, at75, 1.0);
  EXPECT_NEAR(other.angle_deg, (stripe_direction(-7, 2) - stripe_direction(-4, 7)) / kDeg, 3.0);
  EXPECT_NEAR(other.coherence_ratio, 1.0, 0.02);
  EXPECT_GT(other.histogram_distance, 0.9);
  EXPECT_LT(other.aligned_histogram_distance, 0.05);
}

TEST(AppearanceMetrics, DirectionsAreReadOnTheSurfaceWhateverTheChartsTurn) {
  // The stripes projected onto the plane (as a flow map at rest shows
  // them) through a chart turned by 100° and mirrored: on the surface they
  // run as in the exemplar; in the atlas they do not.
  const Exemplar at30(stripes(64, -4, 7));
  const Eigen::Matrix2d turn =
      Eigen::Rotation2Dd(100.0 * kDeg).toRotationMatrix() * Eigen::Vector2d(-1.0, 1.0).asDiagonal();
  const Image atlas = projected(at30, turn, 0.25, 256);  // 4 tiles of 64 texels: scale 1
  const std::vector<char> mask = everywhere(atlas);
  // A window's map from atlas texels to the plane: the chart's, over a
  // large window (triangles centred in it) and a small one (the triangle
  // holding its centre).
  for (int n : {128, 8}) {
    const Eigen::Matrix2d map = window_frames(chart(turn), 256, {{100, 60}}, n, DirectionFrame{}).front();
    EXPECT_TRUE(map.isApprox(turn / 256.0, 1e-9)) << n << "\n" << map * 256.0;
  }
  const OrientationFigures on_surface = orientation_figures(atlas, chart(turn), mask, at30, 1.0);
  EXPECT_LT(on_surface.angle_deg, 3.0);
  EXPECT_NEAR(on_surface.coherence_ratio, 1.0, 0.05);
  const OrientationFigures in_atlas = orientation_figures(atlas, square(), mask, at30, 1.0);
  EXPECT_GT(in_atlas.angle_deg, 20.0);
  EXPECT_LT(in_atlas.aligned_histogram_distance, 0.05);
  // The nearest-window energy reads the windows on the surface too: the
  // exemplar unturned matches its own windows better than the reference's
  // turned ones.
  const Exemplar gravel(make_exemplar("gravel", 64, 5));
  EXPECT_LT(window_energy_ratio(projected(gravel, turn, 0.25, 256), chart(turn), mask, gravel, 1.0), 1.0);
}

TEST(AppearanceMetrics, TheExemplarTiledAtItsScaleMatchesItsOwnOrientation) {
  // What a flow map shows: the exemplar tiled, unrotated, magnified 2×
  // (bilinear): coherence and direction as the exemplar's at that scale.
  const Exemplar brick(bricks());
  const Image atlas = exemplar_crop(brick, 17.2, 40.6, 0.5, 384);
  const std::vector<char> mask = everywhere(atlas);
  const OrientationFigures f = orientation_figures(atlas, square(), mask, brick, 0.5);
  EXPECT_EQ(f.window, 128);  // one tile: 64 / 0.5
  EXPECT_GT(f.exemplar_coherence, 0.3);
  EXPECT_NEAR(f.coherence_ratio, 1.0, 0.1);
  EXPECT_LT(f.angle_deg, 3.0);
  EXPECT_LT(f.histogram_distance, 0.2);
  // Turned by 90°: as coherent, 90° off, the same up to the turn.
  const OrientationFigures t = orientation_figures(turned(atlas), square(), mask, brick, 0.5);
  EXPECT_NEAR(t.coherence_ratio, 1.0, 0.1);
  EXPECT_GT(t.angle_deg, 87.0);
  EXPECT_LT(t.aligned_histogram_distance, 0.2);
  // Gravel is isotropic: a low coherence.
  const Exemplar gravel(make_exemplar("gravel", 64, 5));
  EXPECT_LT(
      orientation_figures(exemplar_crop(gravel, 3.0, 9.0, 1.0, 256), square(), mask, gravel, 1.0).exemplar_coherence,
      0.3);
}

TEST(AppearanceMetrics, WindowEnergyIsAboutOneForACopyAndHigherForAMixture) {
  // A checkerboard, shown shifted by a fraction of a texel (bilinear), or
  // turned on the surface: as close to the exemplar as its own windows.
  const Exemplar board(checker());
  const std::vector<char> mask(256 * 256, 1);
  const Image copy = exemplar_crop(board, 13.3, 7.7, 1.0, 256);
  const double shifted = window_energy_ratio(copy, square(), mask, board, 1.0);
  EXPECT_LT(shifted, 1.2);
  auto turned_by = [&](double degrees, const Vec2& shift) {
    return projected(board, Eigen::Rotation2Dd(degrees * kDeg).toRotationMatrix(), 0.25, 256, shift);
  };
  const double turned = window_energy_ratio(turned_by(33.0, Vec2::Zero()), square(), mask, board, 1.0);
  EXPECT_GT(turned, 0.5);
  EXPECT_LT(turned, 1.5);
  // Two copies overlaid (ghosting), and a copy over a turned one: windows
  // the exemplar does not have.
  const Image other = exemplar_crop(board, 40.1, 29.6, 1.0, 256);
  EXPECT_GT(window_energy_ratio(average(copy, other), square(), mask, board, 1.0), 2.5);
  const Image crossed = average(turned_by(10.0, Vec2::Zero()), turned_by(100.0, Vec2(0.3, 0.1)));
  EXPECT_GT(window_energy_ratio(crossed, square(), mask, board, 1.0), 2.5);
  // Constant grey: far from every window.
  EXPECT_GT(window_energy_ratio(Image::blank(256, 256, 3), square(), mask, board, 1.0), 4.0);
  EXPECT_TRUE(std::isnan(window_energy_ratio(copy, square(), std::vector<char>(mask.size(), 0), board, 1.0)));
}

TEST(AppearanceMetrics, WindowEnergyIsTheSameWhateverTheThreadCount) {
  const Exemplar brick(bricks());
  const Image atlas = exemplar_crop(brick, 3.3, 1.1, 0.7, 160);
  const std::vector<char> mask = everywhere(atlas);
  const double many = window_energy_ratio(atlas, square(), mask, brick, 0.7);
  double one = 0.0;
  tbb::task_arena(1).execute([&] { one = window_energy_ratio(atlas, square(), mask, brick, 0.7); });
  EXPECT_EQ(one, many);
}

TEST(AppearanceMetrics, WassersteinDistanceOfKnownDistributions) {
  EXPECT_DOUBLE_EQ(wasserstein_1d({0.0, 1.0}, {0.5}), 0.5);
  EXPECT_DOUBLE_EQ(wasserstein_1d({2.0, 0.0, 1.0}, {0.0, 1.0, 2.0}), 0.0);
  EXPECT_DOUBLE_EQ(wasserstein_1d({0.0, 1.0, 2.0}, {0.25, 1.25, 2.25}), 0.25);
  EXPECT_DOUBLE_EQ(wasserstein_1d({0.0, 1.0}, {0.0, 0.0, 1.0, 1.0}), 0.0);
  EXPECT_DOUBLE_EQ(wasserstein_1d({0.0, 0.0, 0.0}, {0.0, 3.0}), 1.5);
  EXPECT_TRUE(std::isnan(wasserstein_1d({}, {1.0})));
}

TEST(AppearanceMetrics, HistogramDistanceIsZeroForACopyAndLargeForGrey) {
  const Exemplar gravel(make_exemplar("gravel", 64, 5));
  // Magnified 3× (bilinear): the blur is the exemplar's at that scale too.
  const Image copy = exemplar_crop(gravel, 13.3, 7.7, 1.0 / 3.0, 192);
  const std::vector<char> mask = everywhere(copy);
  EXPECT_LT(value_histogram_distance(copy, mask, gravel, 1.0 / 3.0), 0.05);
  Image grey = Image::blank(192, 192, 3);
  for (std::size_t i = 0; i < grey.pixels.size(); ++i) grey.pixels[i] = gravel.mean()[i % 3];
  EXPECT_GT(value_histogram_distance(grey, mask, gravel, 1.0 / 3.0), 0.5);
  // Washed out: halfway to the mean.
  const double washed = value_histogram_distance(average(copy, grey), mask, gravel, 1.0 / 3.0);
  EXPECT_GT(washed, 0.2);
  EXPECT_LT(washed, value_histogram_distance(grey, mask, gravel, 1.0 / 3.0));
}

/// White noise in [0, 1] on a size² image, grey; with `period` > 0 a
/// period² block of it tiled (the same noise every `period` texels along x
/// and y).
Image noise(int size, int period, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> value(0.0f, 1.0f);
  const int block = period > 0 ? period : size;
  std::vector<float> values(static_cast<std::size_t>(block) * block);
  for (float& v : values) v = value(random);
  Image image = Image::blank(size, size, 1);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) image.at(x, y, 0) = values[texel_index(x % block, y % block, block)];
  }
  return image;
}

TEST(AppearanceMetrics, MeanNearestDistanceOfALattice) {
  // A 5 × 4 lattice 0.3 apart in a tilted plane: every point's nearest is 0.3 away.
  std::vector<Vec3> points;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 5; ++i) points.emplace_back(0.3 * i, 0.3 * j * 0.6, 0.3 * j * 0.8);
  }
  EXPECT_NEAR(mean_nearest_distance(points), 0.3, 1e-12);
  // Far apart pairs: each point's nearest is its partner.
  EXPECT_NEAR(mean_nearest_distance({Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(50, 0, 0), Vec3(50, 0.4, 0)}), 0.25, 1e-12);
  EXPECT_TRUE(std::isnan(mean_nearest_distance({Vec3(1, 2, 3)})));
}

TEST(AppearanceMetrics, NoiseRepeatingAtTheLagCorrelatesThere) {
  // Noise tiled every 32 texels repeats at a lag of 32 along x and y
  // (directions 0 and 4 of 8 over [0, π)), not along the others; the mean
  // over the 8 directions is about 2/8. Noise that never repeats: about 0.
  const std::vector<char> mask(256 * 256, 1);
  const auto windows = chart_windows(mask, 256, 66, 64);
  const Autocorrelation tiled = luminance_autocorrelation(noise(256, 32, 7), windows, 66, 32.0);
  ASSERT_EQ(tiled.by_direction.size(), 8u);
  for (std::size_t k = 0; k < 8; ++k) EXPECT_NEAR(tiled.by_direction[k], k % 4 == 0 ? 1.0 : 0.0, 0.05) << k;
  EXPECT_NEAR(tiled.mean, 0.25, 0.03);
  const Autocorrelation white = luminance_autocorrelation(noise(256, 0, 7), windows, 66, 32.0);
  for (double r : white.by_direction) EXPECT_NEAR(r, 0.0, 0.05);
  EXPECT_NEAR(white.mean, 0.0, 0.02);
  // At a lag of one texel noise tiled or not is as uncorrelated; at 0, 1.
  EXPECT_NEAR(luminance_autocorrelation(noise(256, 32, 7), windows, 66, 1.0).by_direction[0], 0.0, 0.05);
  EXPECT_NEAR(luminance_autocorrelation(noise(256, 32, 7), windows, 66, 0.0).mean, 1.0, 1e-9);
}

TEST(AppearanceMetrics, AnExemplarTiledShowsNoLayout) {
  // Bricks repeat every 64 exemplar texels: 128 atlas texels at scale 0.5.
  // Tiled as a flow map shows them, the atlas correlates as the exemplar
  // does at any lag, its period included.
  const Exemplar brick(bricks());
  const Image atlas = exemplar_crop(brick, 17.2, 40.6, 0.5, 384);
  const std::vector<char> mask = everywhere(atlas);
  for (double lag : {24.0, 45.0, 128.0}) {
    const LayoutFigures f = layout_figures(atlas, mask, brick, 0.5, lag);
    EXPECT_EQ(f.lag, lag);
    EXPECT_NEAR(f.excess, 0.0, 0.05) << lag << ": " << f.atlas << " against " << f.exemplar;
  }
  // At its period the exemplar repeats along x and y (2 of the 8
  // directions) and partly along the others.
  EXPECT_GT(layout_figures(atlas, mask, brick, 0.5, 128.0).exemplar, 0.2);
  // No window inside the charts: nothing to read.
  EXPECT_TRUE(std::isnan(layout_figures(atlas, std::vector<char>(mask.size(), 0), brick, 0.5, 24.0).excess));
}

TEST(AppearanceMetrics, AFeatureRepeatedAtTheLagShowsTheLayout) {
  // Gravel with a bright blob pasted every 32 texels (what patches showing
  // one exemplar region at the patch spacing draw): a clear excess at 32.
  const Exemplar gravel(make_exemplar("gravel", 64, 5));
  Image atlas = exemplar_crop(gravel, 13.3, 7.7, 1.0, 256);
  for (int y = 0; y < 256; ++y) {
    for (int x = 0; x < 256; ++x) {
      const double dx = (x % 32) - 15.5, dy = (y % 32) - 15.5;
      const float blob = static_cast<float>(std::exp(-(dx * dx + dy * dy) / (2.0 * 5.0 * 5.0)));
      for (int c = 0; c < 3; ++c) atlas.at(x, y, c) += blob * (1.0f - atlas.at(x, y, c));
    }
  }
  const std::vector<char> mask = everywhere(atlas);
  const LayoutFigures at_lag = layout_figures(atlas, mask, gravel, 1.0, 32.0);
  EXPECT_GT(at_lag.excess, 0.1) << at_lag.atlas << " against " << at_lag.exemplar;
  EXPECT_NEAR(layout_figures(exemplar_crop(gravel, 13.3, 7.7, 1.0, 256), mask, gravel, 1.0, 32.0).excess, 0.0, 0.03);
  // The same whatever the thread count.
  LayoutFigures one;
  tbb::task_arena(1).execute([&] { one = layout_figures(atlas, mask, gravel, 1.0, 32.0); });
  EXPECT_EQ(one.atlas, at_lag.atlas);
  EXPECT_EQ(one.exemplar, at_lag.exemplar);
}

/// Centres at least `d` apart over a size² image (dart throwing, fixed
/// seed), in texel coordinates (z = 0).
std::vector<Vec3> darts(int size, double d) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> u(0.0, size);
  std::vector<Vec3> centres;
  for (int t = 0; t < 4000; ++t) {
    const Vec3 c(u(random), u(random), 0.0);
    if (std::all_of(centres.begin(), centres.end(), [&](const Vec3& o) { return (o - c).norm() >= d; }))
      centres.push_back(c);
  }
  return centres;
}

/// A size² image of Voronoi cells around `centres` (texel coordinates),
/// each showing `exemplar` at `scale` exemplar texels per texel from the
/// exemplar texel anchors[i] at its centre: patches as a flow of sharp
/// seams, without blending.
Image cells(const Exemplar& exemplar, const std::vector<Vec3>& centres, const std::vector<Vec2>& anchors, double scale,
            int size) {
  Image image = Image::blank(size, size, exemplar.channels());
  const int w = exemplar.image().width, h = exemplar.image().height;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const Vec3 q(x + 0.5, y + 0.5, 0.0);
      std::size_t i = 0;
      for (std::size_t k = 1; k < centres.size(); ++k) {
        if ((centres[k] - q).squaredNorm() < (centres[i] - q).squaredNorm()) i = k;
      }
      const Vec2 e = anchors[i] + scale * (q - centres[i]).head<2>();
      exemplar.sample(px_to_u(e.x(), w), py_to_v(e.y(), h), image.pixel(texel_index(x, y, size)));
    }
  }
  return image;
}

/// Each centre (texel coordinates) with its nearest other, read in an atlas
/// whose texels are the surface's (identity maps).
std::vector<NeighbourPair> plane_pairs(const std::vector<Vec3>& centres) {
  std::vector<NeighbourPair> pairs;
  const std::vector<int> nearest = nearest_others(centres);
  for (std::size_t i = 0; i < centres.size(); ++i) {
    const Vec3 &a = centres[i], &b = centres[static_cast<std::size_t>(nearest[i])];
    pairs.push_back({a.head<2>(), b.head<2>(), Eigen::Matrix2d::Identity(), Eigen::Matrix2d::Identity(),
                     Vec2(b.x() - a.x(), a.y() - b.y())});
  }
  return pairs;
}

TEST(AppearanceMetrics, NeighboursShowingOneExemplarRegionCorrelate) {
  // Cells about 32 texels apart, each showing gravel (a tile of 80 texels)
  // from one anchor, or each from its own: neighbours correlate near 1 in
  // the first and as the exemplar does in the second.
  const Exemplar gravel(make_exemplar("gravel", 64, 5));
  const std::vector<Vec3> centres = darts(256, 30.0);
  const double scale = 0.8, spacing = mean_nearest_distance(centres);
  ASSERT_GT(centres.size(), 30u);
  EXPECT_GT(spacing, 30.0);
  EXPECT_LT(spacing, 45.0);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> u(0.0, 64.0);
  std::vector<Vec2> own, one(centres.size(), Vec2(20.0, 40.0));
  for (std::size_t i = 0; i < centres.size(); ++i) own.emplace_back(u(random), u(random));
  const std::vector<char> mask(256 * 256, 1);
  const int n = static_cast<int>(std::lround(0.5 * spacing));  // views of half the spacing, as eval reads them
  const Image repeating = cells(gravel, centres, one, scale, 256);
  const NeighbourFigures repeated = neighbour_figures(repeating, mask, gravel, scale, plane_pairs(centres), n);
  EXPECT_GT(repeated.pairs, 10);
  EXPECT_GT(repeated.atlas, 0.6);
  EXPECT_GT(repeated.excess, 0.5);
  const Image apart = cells(gravel, centres, own, scale, 256);
  const NeighbourFigures independent = neighbour_figures(apart, mask, gravel, scale, plane_pairs(centres), n);
  EXPECT_NEAR(independent.excess, 0.0, 0.15);
  // The autocorrelation at the spacing in 8 fixed directions hardly sees
  // it: each neighbour repeats at its own displacement, and few of them
  // lie on one of the 8 at the mean distance.
  const double fixed_repeated = layout_figures(repeating, mask, gravel, scale, spacing).excess;
  const double fixed_apart = layout_figures(apart, mask, gravel, scale, spacing).excess;
  EXPECT_LT(fixed_repeated - fixed_apart, 0.1);
  // Views that leave the charts are not read; the same for any thread count.
  std::vector<char> left(mask.size(), 0);
  std::fill(left.begin(), left.begin() + 128 * 256, 1);
  const NeighbourFigures top = neighbour_figures(apart, left, gravel, scale, plane_pairs(centres), n);
  EXPECT_LT(top.pairs, independent.pairs);
  NeighbourFigures single;
  tbb::task_arena(1).execute([&] { single = neighbour_figures(apart, mask, gravel, scale, plane_pairs(centres), n); });
  EXPECT_EQ(single.atlas, independent.atlas);
  EXPECT_EQ(single.exemplar, independent.exemplar);
}

TEST(AppearanceMetrics, NeighbourPairsAreLocatedThroughTheUVMesh) {
  // The unit square, its uvs its x and y, in a 256² atlas: a centre at
  // (x, y) lies at texel (256 x, 256 (1 − y)); the chord to its nearest
  // reads in texels along the frame's axes (x right, y up).
  const TexturedFrame frame(square(), Image::blank(256, 256, 3));
  const std::vector<Vec3> centres{Vec3(0.25, 0.5, 0.0), Vec3(0.5, 0.5, 0.0), Vec3(0.5, 0.875, 0.0)};
  const std::vector<NeighbourPair> pairs = neighbour_pairs(frame.mesh, *frame.surface, 256, centres, 256.0, 16);
  ASSERT_EQ(pairs.size(), 2u);  // 0 ↔ 1 once, 2 → 1
  EXPECT_TRUE(pairs[0].from.isApprox(Vec2(64.0, 128.0), 1e-9)) << pairs[0].from.transpose();
  EXPECT_TRUE(pairs[0].to.isApprox(Vec2(128.0, 128.0), 1e-9));
  EXPECT_TRUE(pairs[0].displacement.isApprox(Vec2(64.0, 0.0), 1e-9));
  EXPECT_TRUE(pairs[1].from.isApprox(Vec2(128.0, 32.0), 1e-9));
  EXPECT_TRUE(pairs[1].displacement.isApprox(Vec2(0.0, -96.0), 1e-9));
  EXPECT_TRUE(pairs[0].from_map.isApprox(Eigen::Matrix2d::Identity() / 256.0, 1e-9));
}

}  // namespace
}  // namespace fluidtex
