// Patch advection (tracking/advection.h): Euler and Heun on known motions.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "fluidtex/tracking/advection.h"
#include "fluidtex/tracking/patch.h"
#include "fluidtex/tracking/patch_builder.h"
#include "fluidtex/tracking/tracker.h"
#include "mesh_fixtures.h"
#include "test_util.h"

namespace fluidtex {
namespace {

TEST(Advection, HeunFollowsARotationToSecondOrder) {
  // A sphere spinning at 0.1 rad per frame, its velocity ω × x the same in
  // both frames and stored at the vertices (linear, so exact on the facets):
  // Heun lands within a tenth of Euler's error of the rotated point, over the
  // whole sphere (--advection heun for velocities sampled at the frame's
  // instant, as analytic flows give them).
  FrameMesh sphere = test::uv_sphere(48, 96, 1.0);
  const Vec3 omega(0.3, -0.2, 2.4);
  for (std::size_t v = 0; v < sphere.positions.size(); ++v) sphere.velocities[v] = omega.cross(sphere.positions[v]);
  const SurfaceIndex surface(sphere);
  const double dt = 1.0 / 24;
  const Eigen::AngleAxisd turn(omega.norm() * dt, omega.normalized());
  double euler = 0.0, heun = 0.0;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const SurfacePoint from = surface.closest_point(Vec3(u(rng), u(rng), u(rng)));
    ASSERT_TRUE(from.valid());
    const Vec3 exact = turn * from.position;
    euler = std::max(euler, (advect_target(from, surface, surface, dt, Advection::Euler) - exact).norm());
    heun = std::max(heun, (advect_target(from, surface, surface, dt, Advection::Heun) - exact).norm());
  }
  EXPECT_GT(euler, 1e-3);  // θ²/2 at the equator
  EXPECT_LT(heun, 0.1 * euler);
}

TEST(Advection, EulerMovesBySolverVelocityOfTheFrame) {
  // Accelerating liquid: the solver stores with frame f the velocity that
  // carried it to f+1 (1 m/s); the next frame already holds the next step's
  // (3 m/s). The default (Euler) moves by v_f·dt, Heun by the average.
  const FrameMesh before = test::flat_grid(20, 1.0, 0.0, 0.0, 0.0, [](const Vec3&) { return Vec3(1, 0, 0); });
  const FrameMesh after = test::flat_grid(20, 1.0, 0.0, 0.0, 0.0, [](const Vec3&) { return Vec3(3, 0, 0); });
  const SurfaceIndex previous(before), next(after);
  const double dt = 0.05;
  const SurfacePoint from = previous.closest_point(Vec3(0.4, 0.5, 0.0));
  const Vec3 step = Vec3(1, 0, 0) * dt;
  EXPECT_EQ(TrackerSettings{}.advection, Advection::Euler);
  EXPECT_NEAR((advect_target(from, previous, next, dt, Advection::Euler) - from.position - step).norm(), 0.0, 1e-12);
  EXPECT_NEAR((advect_target(from, previous, next, dt, Advection::Heun) - from.position - 2.0 * step).norm(), 0.0,
              1e-12);
}

}  // namespace
}  // namespace fluidtex
