// Plastic patches (tracking/relaxation): a rigid motion leaves a patch's uv
// alone, a stretch relaxes by the given share, and under a sustained stretch
// patches survive with relaxation where the paper's rules retire them.
#include <gtest/gtest.h>

#include <cmath>

#include "fluidtex/tracking/advection.h"
#include "fluidtex/tracking/patch_builder.h"
#include "fluidtex/tracking/patch_distortion.h"
#include "fluidtex/tracking/relaxation.h"
#include "fluidtex/tracking/tracker.h"
#include "mesh_fixtures.h"

namespace fluidtex {
namespace {

TrackingOptions grid_options() {
  TrackingOptions o;
  o = o.resolved(1.0);
  o.radius = 0.15;
  o.max_projection = 0.25 * 0.15;
  return o;
}

/// A remeshed patch on a flat unit grid, centred at (0.5, 0.5).
Patch grid_patch(const SurfaceIndex& surface, const TrackingOptions& o) {
  SurfaceSample centre;
  centre.point = surface.closest_point(Vec3(0.5, 0.5, 0.0));
  centre.normal = surface.normal_at(centre.point);
  std::string why;
  auto patch = build_patch(surface, centre, o, 1, 1, 1, 0.25 * o.d(), &why);
  EXPECT_TRUE(patch) << why;
  return patch ? *patch : Patch{};
}

/// Moves every vertex of `patch` by `f` and projects it onto `surface`.
template <class F>
void move_patch(Patch& patch, const SurfaceIndex& surface, F&& f) {
  for (std::size_t v = 0; v < patch.num_vertices(); ++v) {
    patch.projections[v] = surface.closest_point(f(patch.positions[v]));
    patch.positions[v] = patch.projections[v].position;
  }
}

/// The 3D point of `patch` at uv 0 (the disk centre the texture shows there).
Vec3 point_at_origin(const Patch& patch) {
  for (const Tri& t : patch.triangles) {
    const Vec2 a = patch.uvs[t[0]], b = patch.uvs[t[1]], c = patch.uvs[t[2]];
    const double area = signed_area(a, b, c);
    const double l0 = signed_area(Vec2::Zero(), b, c) / area, l1 = signed_area(a, Vec2::Zero(), c) / area;
    const double l2 = 1.0 - l0 - l1;
    if (l0 >= -1e-12 && l1 >= -1e-12 && l2 >= -1e-12) return interpolate(patch.positions, t, Vec3(l0, l1, l2));
  }
  ADD_FAILURE() << "no triangle over uv 0";
  return Vec3::Zero();
}

TEST(Relaxation, RigidMotionLeavesTheUvAlone) {
  const FrameMesh grid = test::flat_grid(40);
  const SurfaceIndex surface(grid);
  const TrackingOptions o = grid_options();
  Patch patch = grid_patch(surface, o);
  ASSERT_FALSE(patch.empty());
  // Rotate the grid and the patch by 30° about the z axis through (0.5, 0.5).
  const Eigen::AngleAxisd turn(M_PI / 6, Vec3::UnitZ());
  auto rigid = [&](const Vec3& p) { return Vec3(turn * (p - Vec3(0.5, 0.5, 0)) + Vec3(0.5, 0.5, 0)); };
  FrameMesh turned = grid;
  for (Vec3& p : turned.positions) p = rigid(p);
  const SurfaceIndex turned_surface(turned);
  const std::vector<Vec2> before = patch.uvs;
  move_patch(patch, turned_surface, rigid);
  EXPECT_FALSE(relax_patch(patch, 1.0, o.relax_yield(), o));  // nothing beyond the yield: untouched
  EXPECT_EQ(patch.uvs, before);
  relax_patch(patch, 1.0, 1.0, o);  // towards the isometric shape, which it has
  for (std::size_t v = 0; v < before.size(); ++v) EXPECT_NEAR((patch.uvs[v] - before[v]).norm(), 0.0, 1e-9);
  EXPECT_EQ(update_distortion(patch, turned_surface, o), RetireCause::None);
  EXPECT_NEAR(patch.max_distortion, 1.0, 1e-6);
}

TEST(Relaxation, StretchRelaxesByTheRateAndTheCentreStays) {
  const FrameMesh grid = test::flat_grid(40);
  const TrackingOptions o = grid_options();
  const Patch fresh = grid_patch(SurfaceIndex(grid), o);
  ASSERT_FALSE(fresh.empty());
  // Stretch 1.8× along x and squeeze along y (area kept) about the centre.
  auto stretch = [](const Vec3& p) { return Vec3(0.5 + 1.8 * (p.x() - 0.5), 0.5 + (p.y() - 0.5) / 1.8, 0.0); };
  FrameMesh stretched = grid;
  for (Vec3& p : stretched.positions) p = stretch(p);
  const SurfaceIndex surface(stretched);

  Patch unrelaxed = fresh;
  move_patch(unrelaxed, surface, stretch);
  update_distortion(unrelaxed, surface, o);
  EXPECT_NEAR(unrelaxed.max_distortion, 1.8, 1e-6);

  Patch full = fresh, half = fresh, yielded = fresh;
  move_patch(full, surface, stretch);
  move_patch(half, surface, stretch);
  move_patch(yielded, surface, stretch);
  ASSERT_TRUE(relax_patch(full, 1.0, 1.0, o));
  ASSERT_TRUE(relax_patch(half, 0.5, 1.0, o));
  ASSERT_TRUE(relax_patch(yielded, 1.0, 1.5, o));
  update_distortion(full, surface, o);
  update_distortion(half, surface, o);
  update_distortion(yielded, surface, o);
  EXPECT_NEAR(full.max_distortion, 1.0, 1e-6);  // a flat shape flattens onto itself
  EXPECT_GT(half.max_distortion, 1.1);
  EXPECT_LT(half.max_distortion, 1.6);
  EXPECT_NEAR(yielded.max_distortion, 1.5, 1e-6);  // only the stretch beyond the yield is taken out
  // The texture's centre stays on the disk centre, and the texture keeps its
  // metric scale: uv area equals 3D area once fully relaxed.
  EXPECT_NEAR((point_at_origin(full) - Vec3(0.5, 0.5, 0)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((point_at_origin(half) - Vec3(0.5, 0.5, 0)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((point_at_origin(yielded) - Vec3(0.5, 0.5, 0)).norm(), 0.0, 1e-9);
  double area_uv = 0.0, area_3d = 0.0;
  for (const Tri& t : full.triangles)
    area_uv += triangle_area(full.uvs, t), area_3d += triangle_area(full.positions, t);
  EXPECT_NEAR(area_uv, area_3d, 1e-8);
}

/// A plane in a stagnation-point flow about its centre: the liquid
/// stretches along x without end (e^{a t}). The velocity stored with a frame
/// carries it to the next (the solver's convention), ((e^{a dt} − 1) x,
/// (e^{−a dt} − 1) y) / dt.
std::shared_ptr<const FrameMesh> strained_plane(double a, double dt) {
  const double ax = std::expm1(a * dt) / dt, ay = std::expm1(-a * dt) / dt;
  return std::make_shared<const FrameMesh>(
      test::flat_grid(24, 0.8, 0.0, -0.4, -0.4, [=](const Vec3& p) { return Vec3(ax * p.x(), ay * p.y(), 0.0); }));
}

TEST(Relaxation, FewerPatchesAreRetiredAsStretchedInASustainedStretch) {
  // 48 frames at 24 fps with a = 0.6/s (2.5 % per frame) stretch the liquid
  // by e^1.2 ≈ 3.3. The paper's rules retire patches as too distorted once
  // they pass what Q_vmin allows; plastic patches (the default) follow the
  // flow just as closely and stay less distorted, so fewer are retired, and
  // the one at the stagnation point lives until what stretch does to any
  // Poisson distribution (rows of disks squeezed together) retires it.
  constexpr double a = 0.6, dt = 1.0 / 24;
  struct Run {
    int stretched = 0;          // retirements as too distorted
    int centre_live_until = 1;  // last frame the patch nearest the stagnation point was live
    double centre_max_distortion = 1.0;
    double centre_off_path = 0.0;  // largest distance of its centre from where the flow carries it
  };
  auto track = [&](int relax_frames) {
    TrackerSettings s;
    s.tracking.radius = 0.1;
    if (relax_frames >= 0) s.tracking.relax_frames = relax_frames;
    s.tracking.distorted = Distorted::Fade;  // retirements are what this compares, not recuts
    // The stretch alone: recutting the patches beside the strips the inflow
    // bares along the window's edges would undo their stretch too.
    s.tracking.gap_fill = GapFill::Seed;
    s.seed = 3;
    Tracker t(s);
    Run run;
    t.step(strained_plane(a, dt), 1, dt);
    std::uint32_t centre_id = 0;
    double nearest = 1e9;
    Vec3 start;
    for (const Patch& p : t.patches()) {
      const double r = p.centre.point.position.norm();
      if (r < nearest) nearest = r, centre_id = p.id, start = p.centre.point.position;
    }
    for (int f = 2; f <= 48; ++f) {
      const StepReport r = t.step(strained_plane(a, dt), f, dt);
      for (const RetiredPatch& x : r.retired) run.stretched += x.cause == RetireCause::Quality;
      for (const Patch& p : t.patches()) {
        if (p.id != centre_id || is_fading_out(p.state)) continue;
        const double time = (f - 1) * dt;
        const Vec3 path(start.x() * std::exp(a * time), start.y() * std::exp(-a * time), 0.0);
        run.centre_live_until = f;
        run.centre_max_distortion = std::max(run.centre_max_distortion, p.max_distortion);
        run.centre_off_path = std::max(run.centre_off_path, (p.centre.point.position - path).norm());
      }
    }
    return run;
  };
  const Run paper = track(0);
  EXPECT_GT(paper.stretched, 20);
  EXPECT_LT(paper.centre_live_until, 40);
  const Run plastic = track(-1);  // the default
  // Measured: 118 retirements as stretched with the paper's rules, 46
  // plastic (at 2.5 % per frame the excess over the yield settles near
  // 1.5·e^(7·0.025) ≈ 1.8 with relax-frames 8); the centre patch retired at
  // frame 28 (D = 1.96) against live to frame 40 (D ≤ 1.80), when the kill
  // distance takes it, its centre on the flow's path to 1e-8.
  EXPECT_LT(plastic.stretched, paper.stretched / 2);
  EXPECT_GT(plastic.centre_live_until, paper.centre_live_until);
  EXPECT_LT(plastic.centre_max_distortion, 1.8);
  EXPECT_LT(plastic.centre_off_path, 2e-3);
}

}  // namespace
}  // namespace fluidtex
