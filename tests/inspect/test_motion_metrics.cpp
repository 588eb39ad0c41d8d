// Whether the texture moves with the liquid: the warping error and the
// optical flow on textures moved by a known amount.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <optional>

#include "fluidtex/inspect/motion_metrics.h"
#include "fluidtex/scenes/exemplar_gen.h"
#include "mesh_fixtures.h"

namespace fluidtex {
namespace {

TEST(MotionMetrics, WarpingErrorIsZeroForAnAdvectedTextureAndLargeForARandomOne) {
  const Exemplar exemplar(make_exemplar("gravel", 128, 4));
  const double dt = 1.0 / 24.0, speed = 0.12;  // the surface moves 5 mm per frame along x
  FrameMesh mesh = test::flat_grid(10, 1.0, 0.0, 0.0, 0.0);
  mesh.velocities.assign(mesh.positions.size(), Vec3(speed, 0.0, 0.0));
  const TexturedFrame t0(test::textured_grid(10, 0.0), exemplar.image());
  std::optional<TexturedFrame> moved;  // frames are moved around by eval: the index must follow
  moved.emplace(TexturedFrame(test::textured_grid(10, speed * dt), exemplar.image()));
  const TexturedFrame t1(std::move(*moved));
  moved.reset();
  const WarpingError w = warping_error(mesh, t0, t1, LiquidMotion(dt), exemplar, 4000, 7);
  EXPECT_EQ(w.samples, 4000u);
  EXPECT_LT(w.advected, 1e-3);  // exactly advected, no distortion
  EXPECT_GT(w.fixed, 0.1);      // the texture moved under a fixed point
  EXPECT_GT(w.random, 0.5);     // uncorrelated colours: about 2/sqrt(pi) σ for Gaussian noise
  // A texture unrelated to the last frame's: as bad as random.
  const TexturedFrame other(test::textured_grid(10, speed * dt), make_exemplar("gravel", 128, 99));
  const WarpingError r = warping_error(mesh, t0, other, LiquidMotion(dt), exemplar, 4000, 7);
  EXPECT_GT(r.advected, 0.5 * w.random);
}

TEST(MotionMetrics, TheLiquidIsCarriedThroughTheFramesBetweenTwoMeasured) {
  // Frame t moves along x; the frame after it, which a stepped run skips,
  // moves along y: two frames later a point has gone both ways.
  const double dt = 1.0 / 24.0;
  FrameMesh between = test::flat_grid(10, 1.0, 0.0, 0.0, 0.0);
  between.velocities.assign(between.positions.size(), Vec3(0.0, 0.6, 0.0));
  LiquidMotion motion(dt);
  EXPECT_TRUE(motion.carry(Vec3(0.5, 0.5, 0.0), Vec3(0.3, 0.0, 0.0)).isApprox(Vec3(0.5 + 0.3 * dt, 0.5, 0.0)));
  motion.add_step(std::make_shared<const FrameMesh>(between), 2 * dt);
  EXPECT_TRUE(
      motion.carry(Vec3(0.5, 0.5, 0.0), Vec3(0.3, 0.0, 0.0)).isApprox(Vec3(0.5 + 0.3 * dt, 0.5 + 1.2 * dt, 0.0), 1e-9));

  // A texture that went along x and then along y is where the motion says.
  const Exemplar exemplar(make_exemplar("gravel", 128, 4));
  FrameMesh mesh = test::flat_grid(10, 1.0, 0.0, 0.0, 0.0);
  mesh.velocities.assign(mesh.positions.size(), Vec3(0.3, 0.0, 0.0));
  const TexturedFrame t0(test::textured_grid(10, 0.0), exemplar.image());
  UVMesh moved = test::textured_grid(10, 0.3 * dt);
  for (Vec3& p : moved.positions) p.y() += 1.2 * dt;  // uvs stay: the texture moves with it
  const TexturedFrame t2(std::move(moved), exemplar.image());
  EXPECT_LT(warping_error(mesh, t0, t2, motion, exemplar, 4000, 7).advected, 1e-3);
  EXPECT_GT(warping_error(mesh, t0, t2, LiquidMotion(3 * dt), exemplar, 4000, 7).advected, 0.1);
}

TEST(MotionMetrics, OpticalFlowFindsATranslation) {
  const Image texture = make_exemplar("gravel", 128, 5);
  const int n = 96, dx = 2, dy = 1;
  Image a, b, expected;
  a.width = b.width = expected.width = a.height = b.height = expected.height = n;
  a.channels = b.channels = 3;
  expected.channels = 2;
  a.pixels.resize(n * n * 3), b.pixels.resize(n * n * 3), expected.pixels.resize(n * n * 2);
  std::vector<char> mask(n * n, 0);
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      for (int c = 0; c < 3; ++c) {
        a.pixels[(y * n + x) * 3 + c] = texture.at(x + 8, y + 8, c);
        b.pixels[(y * n + x) * 3 + c] = texture.at(x + 8 - dx, y + 8 - dy, c);  // content moved by (dx, dy)
      }
      expected.pixels[(y * n + x) * 2] = dx, expected.pixels[(y * n + x) * 2 + 1] = dy;
      mask[y * n + x] = x >= 16 && y >= 16 && x < n - 16 && y < n - 16;
    }
  }
  const FlowError e = optical_flow_error(a, b, expected, mask);
  EXPECT_GT(e.pixels, 3000u);
  EXPECT_LT(e.endpoint, 0.3);
  EXPECT_LT(e.angular, 5.0);
  EXPECT_NEAR(e.speed, std::hypot(dx, dy), 1e-9);
  // Against a wrong expectation the error is about the difference.
  for (std::size_t i = 0; i < expected.pixels.size(); i += 2) expected.pixels[i] = -dx;
  EXPECT_GT(optical_flow_error(a, b, expected, mask).endpoint, 3.0);
  // Pixels expected to move by the limit or more count in the overall means
  // only: here the left half, expected at 20 px.
  std::size_t slow = 0;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      expected.pixels[(y * n + x) * 2] = x < n / 2 ? 20.0f : dx;
      slow += mask[y * n + x] && x >= n / 2;
    }
  }
  const FlowError fast = optical_flow_error(a, b, expected, mask, 15.0);
  EXPECT_EQ(fast.pixels, e.pixels);
  EXPECT_EQ(fast.slow_pixels, slow);
  EXPECT_GT(fast.endpoint, 5.0);
  EXPECT_LT(fast.slow_endpoint, 0.3);
  EXPECT_NEAR(fast.slow_speed, std::hypot(dx, dy), 1e-9);
  EXPECT_EQ(optical_flow_error(a, b, expected, mask, 25.0).slow_pixels, e.pixels);
}

}  // namespace
}  // namespace fluidtex
