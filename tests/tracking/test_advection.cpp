// Patch advection (tracking/advection.h): Euler and Heun on known motions;
// centres that miss the surface, leave through an outflow or ride a moving
// rim; the projection slack on fast sheets.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>

#include "fluidtex/tracking/advection.h"
#include "fluidtex/tracking/patch.h"
#include "fluidtex/tracking/patch_builder.h"
#include "fluidtex/tracking/patch_locator.h"
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

TEST(Advection, APatchWhoseCentreMissesTheSurfaceIsMovedAndRecutNotLost) {
  // Still liquid whose next frame has sunk by 2 mpt within `r` of a patch's
  // centre (a closed surface moving away, not a hole: a hole's rim would be
  // an outflow): the centre misses the surface by more than mpt, most of
  // the patch still lies on it.
  const FrameMesh before = test::flat_grid(40);
  const SurfaceIndex previous(before);
  const Vec3 c0(0.45, 0.5, 0);
  TrackingOptions o = TrackingOptions{}.resolved(1.0);
  o.radius = 0.15;
  const double depth = 2.0 * o.mpt();
  const auto sunk = [&](double r) {
    FrameMesh m = before;
    for (Vec3& p : m.positions) {
      if ((p - c0).norm() < r) p.z() -= depth;
    }
    return m;
  };
  const FrameMesh after = sunk(0.1);
  const SurfaceIndex next(after);
  ASSERT_GT((next.closest_point(c0).position - c0).norm(), o.mpt());
  SurfaceSample c;
  c.point = previous.closest_point(c0);
  c.normal = previous.normal_at(c.point);
  const std::optional<Patch> built = build_patch(previous, c, o, 7, 1, 1, 0.25 * o.d());
  ASSERT_TRUE(built);
  const auto advect = [&](Patch& patch, const SurfaceIndex& to) {
    return advect_patch(patch, previous, to, 1.0 / 24, o, Advection::Heun, PatchMotion::Smooth);
  };

  // The paper's rule (--distorted fade): the patch is lost.
  o.distorted = Distorted::Fade;
  Patch lost = *built;
  EXPECT_EQ(advect(lost, next), AdvectResult::CentreLost);

  // With recut: the centre moves onto the sunk surface and the patch is cut
  // again there, with its identity.
  o.distorted = Distorted::Recut;
  Patch moved = *built;
  ASSERT_EQ(advect(moved, next), AdvectResult::CentreMoved);
  EXPECT_TRUE(moved.centre.point.valid());
  EXPECT_NEAR(moved.centre.point.position.z(), -depth, 1e-9);
  const std::optional<Patch> cut = recut_patch(moved, next, o, 1, 2, 0.25 * o.d());
  ASSERT_TRUE(cut);
  EXPECT_EQ(cut->id, built->id);

  // A patch that has sunk entirely is lost even with recut.
  const FrameMesh gone = sunk(0.3);
  const SurfaceIndex far(gone);
  Patch over = *built;
  EXPECT_EQ(advect(over, far), AdvectResult::CentreLost);
}

TEST(ProjectionSlack, AFastSheetWhoseVelocityOverpredictsItsNormalMotionKeepsItsPatch) {
  // A sheet rising at w with a tangential drift u, whose next frame lies at
  // 0.7 of w·dt (the solver's velocity over-predicts the normal motion by
  // 30 %, as on the dam break's fast sheets): advected points land 1.2 mpt
  // beyond it. mpt alone loses the patch; the slack keeps it, carried by
  // u·dt along the sheet.
  TrackingOptions o = TrackingOptions{}.resolved(1.0);
  o.radius = 0.15;
  const double dt = 1.0 / 24, rise = 4.0 * o.mpt(), u = 0.02 / dt;
  const Vec3 velocity(u, 0.0, rise / dt);
  const FrameMesh before = test::flat_grid(40, 1.0, 0.0, 0.0, 0.0, [&](const Vec3&) { return velocity; });
  const FrameMesh after = test::flat_grid(40, 1.0, 0.7 * rise, 0.0, 0.0, [&](const Vec3&) { return velocity; });
  const SurfaceIndex previous(before), next(after);
  SurfaceSample c;
  c.point = previous.closest_point(Vec3(0.5, 0.5, 0));
  c.normal = previous.normal_at(c.point);
  const std::optional<Patch> built = build_patch(previous, c, o, 7, 1, 1, 0.25 * o.d());
  ASSERT_TRUE(built);
  const auto advect = [&](Patch& patch, const SurfaceIndex& to) {
    return advect_patch(patch, previous, to, dt, o, Advection::Euler, PatchMotion::Smooth);
  };
  EXPECT_NEAR(projection_tolerance(c.point, c.normal, c.point.position + velocity * dt, o),
              o.mpt() + o.projection_slack * rise, 1e-12);

  o.projection_slack = 0.0;  // the paper: beyond mpt, lost
  Patch paper = *built;
  EXPECT_EQ(advect(paper, next), AdvectResult::CentreLost);

  o.projection_slack = TrackingOptions{}.projection_slack;
  ASSERT_GE(o.projection_slack * rise + o.mpt(), 1.2 * o.mpt());
  Patch kept = *built;
  ASSERT_EQ(advect(kept, next), AdvectResult::Kept);
  EXPECT_EQ(kept.num_vertices(), built->num_vertices());
  EXPECT_NEAR(kept.centre.point.position.x(), 0.5 + u * dt, 1e-9);
  EXPECT_NEAR(kept.centre.point.position.z(), 0.7 * rise, 1e-9);

  // Motion along the sheet earns no slack: the same sheet drifting at u
  // alone while the next frame jumps by 2 mpt has left the liquid.
  const FrameMesh drift = test::flat_grid(40, 1.0, 0.0, 0.0, 0.0, [&](const Vec3&) { return Vec3(u, 0, 0); });
  const FrameMesh jumped =
      test::flat_grid(40, 1.0, 2.0 * o.mpt(), 0.0, 0.0, [&](const Vec3&) { return Vec3(u, 0, 0); });
  const SurfaceIndex drifting(drift), away(jumped);
  c.point = drifting.closest_point(Vec3(0.5, 0.5, 0));
  c.normal = drifting.normal_at(c.point);
  std::optional<Patch> gone = build_patch(drifting, c, o, 7, 1, 1, 0.25 * o.d());
  ASSERT_TRUE(gone);
  EXPECT_EQ(advect_patch(*gone, drifting, away, dt, o, Advection::Euler, PatchMotion::Smooth),
            AdvectResult::CentreLost);
}

TEST(Advection, APatchWhoseCentreLeavesThroughAnOutflowFadesOutOnTheRim) {
  // Liquid flowing out through the open edge x = 1: a patch whose centre has
  // left through it stays on the rim to fade out, whether the centre went
  // past the edge by more than mpt or by less (then, taken back onto the rim
  // as a near miss, it would stay there for good), and its motion is the
  // liquid's, which sets the pace of the fade.
  TrackingOptions o = TrackingOptions{}.resolved(1.0);
  o.radius = 0.15;
  o.distorted = Distorted::Recut;
  for (const double beyond : {2.0 * o.mpt(), 0.5 * o.mpt()}) {
    const double shift = 0.05 + beyond;  // the centre starts 0.05 inside the edge
    const FrameMesh flow = test::flat_grid(40, 1.0, 0.0, 0.0, 0.0, [&](const Vec3&) { return Vec3(24 * shift, 0, 0); });
    const SurfaceIndex previous(flow), next(flow);
    SurfaceSample c;
    c.point = previous.closest_point(Vec3(0.95, 0.5, 0));
    c.normal = previous.normal_at(c.point);
    std::optional<Patch> patch = build_patch(previous, c, o, 7, 1, 1, 0.25 * o.d());
    ASSERT_TRUE(patch);
    EXPECT_EQ(advect_patch(*patch, previous, next, 1.0 / 24, o, Advection::Euler, PatchMotion::Smooth),
              AdvectResult::LeftThroughRim)
        << beyond;
    EXPECT_NEAR(patch->centre.point.position.x(), 1.0, 1e-9) << beyond;
    EXPECT_NEAR(patch->motion, shift / o.d(), 1e-6) << beyond;
  }
}

TEST(Rim, AnOutlineThatMovesWithTheLiquidKeepsItsRimAndAnInflowRimLetsGo) {
  // An open sheet spreading along x at 6 % per frame, its velocity sampled
  // at the frame's instant (k·x, as analytic scenes store it): Euler lags
  // the moving rim by ½·k²x·dt² a frame. A patch on the rim keeps its rim
  // vertices and its centre on the rim, frame after frame.
  const double k = 1.5, dt = 1.0 / 24;
  auto sheet = [&](double width) {
    FrameMesh m = test::flat_grid(24, 1.2, 0.0, -0.6, -0.6);
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
      m.positions[v].x() *= width;
      m.velocities[v] = Vec3(k * m.positions[v].x(), 0.0, 0.0);
    }
    return m;
  };
  TrackingOptions o = TrackingOptions{}.resolved(1.0);
  o.radius = 0.15;
  std::vector<FrameMesh> frames;
  for (int f = 0; f < 7; ++f) frames.push_back(sheet(std::exp(k * dt * f)));
  SurfaceIndex first(frames[0]);
  SurfaceSample c;
  c.point = first.closest_point(Vec3(0.6, 0.05, 0));
  c.normal = first.normal_at(c.point);
  std::optional<Patch> patch = build_patch(first, c, o, 7, 1, 1, 0.25 * o.d());
  ASSERT_TRUE(patch);
  int on_rim = 0;
  for (int f = 1; f < 7; ++f) {
    const SurfaceIndex previous(frames[f - 1]), next(frames[f]);
    std::vector<char> was(patch->num_vertices());
    for (std::size_t v = 0; v < was.size(); ++v) was[v] = previous.on_boundary(patch->projections[v]);
    ASSERT_NE(advect_patch(*patch, previous, next, dt, o, Advection::Euler, PatchMotion::Smooth),
              AdvectResult::CentreLost);
    ASSERT_EQ(patch->num_vertices(), was.size());  // nothing lost past the rim
    const double rim = 0.6 * std::exp(k * dt * f);
    EXPECT_NEAR(patch->centre.point.position.x(), rim, 1e-9) << f;
    for (std::size_t v = 0; v < was.size(); ++v) {
      if (!was[v] || std::abs(patch->positions[v].y()) > 0.59) continue;  // the corners are another matter
      ++on_rim;
      EXPECT_NEAR(patch->positions[v].x(), rim, 1e-9) << f;
    }
  }
  EXPECT_GT(on_rim, 12);

  // Liquid entering through the still rim x = 0: the rim stays, the
  // liquid moves away from it, and so do the patch's rim vertices.
  const Vec3 inflow(0.5, 0, 0);
  const FrameMesh still = test::flat_grid(40, 1.0, 0.0, 0.0, 0.0, [&](const Vec3&) { return inflow; });
  const SurfaceIndex surface(still);
  c.point = surface.closest_point(Vec3(0.0, 0.5, 0));
  c.normal = surface.normal_at(c.point);
  std::optional<Patch> entering = build_patch(surface, c, o, 7, 1, 1, 0.25 * o.d());
  ASSERT_TRUE(entering);
  const Patch before = *entering;
  ASSERT_NE(advect_patch(*entering, surface, surface, dt, o, Advection::Euler, PatchMotion::Smooth),
            AdvectResult::CentreLost);
  ASSERT_EQ(entering->num_vertices(), before.num_vertices());
  EXPECT_NEAR((entering->centre.point.position - before.centre.point.position - inflow * dt).norm(), 0.0, 1e-9);
  for (std::size_t v = 0; v < before.num_vertices(); ++v)
    EXPECT_NEAR((entering->positions[v] - before.positions[v] - inflow * dt).norm(), 0.0, 1e-9);
}

}  // namespace
}  // namespace fluidtex
