// How much an atlas still looks like its exemplar: orientation, nearest-
// window energy and colour distribution, each on procedural images with a
// known answer (stripes at known angles, bricks, noise, blends of copies).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include <oneapi/tbb/task_arena.h>

#include "fluidtex/inspect/appearance_metrics.h"
#include "fluidtex/inspect/texture_metrics.h"
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

}  // namespace
}  // namespace fluidtex
