// Tracking stages: the paper's equations on known inputs, sampling
// properties, patch creation, and the tracker's determinism and state.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include <oneapi/tbb/global_control.h>

#include "fluidtex/geometry/distortion.h"
#include "fluidtex/scenes/scenes.h"
#include "fluidtex/tracking/advection.h"
#include "fluidtex/tracking/fading.h"
#include "fluidtex/tracking/patch.h"
#include "fluidtex/tracking/patch_builder.h"
#include "fluidtex/tracking/patch_locator.h"
#include "fluidtex/tracking/poisson.h"
#include "fluidtex/tracking/tracker.h"
#include "fluidtex/util/error.h"
#include "mesh_fixtures.h"
#include "test_util.h"

namespace fluidtex {
namespace {

// --- Eq. 1 and the plane test ----------------------------------------------

TEST(PoissonCriterion, EllipsoidKInTangentSpace) {
  const Vec3 p(1, 2, 3), n(0, 0, 1);
  EXPECT_DOUBLE_EQ(ellipsoid_k(p, n, p, 0.5, 0.1), 0.0);
  EXPECT_NEAR(ellipsoid_k(p, n, p + Vec3(0.5, 0, 0), 0.5, 0.1), 1.0, 1e-12);  // on the rim
  EXPECT_NEAR(ellipsoid_k(p, n, p + Vec3(0, 0, 0.1), 0.5, 0.1), 1.0, 1e-12);  // on the cap
  EXPECT_NEAR(ellipsoid_k(p, n, p + Vec3(0.3, 0.4, 0), 0.5, 0.1), 1.0, 1e-12);
  EXPECT_LT(ellipsoid_k(p, n, p + Vec3(0.2, 0.2, 0.05), 0.5, 0.1), 1.0);
  EXPECT_GT(ellipsoid_k(p, n, p + Vec3(0.0, 0.0, 0.15), 0.5, 0.1), 1.0);  // above the thin shell
  // A tilted frame: the normal along x makes x the thin axis.
  EXPECT_GT(ellipsoid_k(p, Vec3(1, 0, 0), p + Vec3(0.2, 0, 0), 0.5, 0.1), 1.0);
  EXPECT_LT(ellipsoid_k(p, Vec3(1, 0, 0), p + Vec3(0, 0.4, 0), 0.5, 0.1), 1.0);
}

TEST(PoissonCriterion, PlaneTestAndCriteria) {
  PoissonParams params{0.5, 0.1, 0.5, Criterion::Ellipsoid};
  const Vec3 p(0, 0, 0), up(0, 0, 1), down(0, 0, -1);
  const Vec3 tilted = Vec3(1, 0, 1).normalized();  // dot 0.707 > 0.5
  EXPECT_TRUE(same_plane(up, tilted, 0.5));
  EXPECT_FALSE(same_plane(up, Vec3(1, 0, 0.2).normalized(), 0.5));
  EXPECT_TRUE(rejects(p, up, Vec3(0.2, 0, 0), up, 0.5, params));
  EXPECT_FALSE(rejects(p, up, Vec3(0.2, 0, 0), down, 0.5, params));  // other side of a sheet
  EXPECT_FALSE(rejects(p, up, Vec3(0, 0, 0.2), up, 0.5, params));    // a layer above, beyond cs
  params.criterion = Criterion::Plane;
  EXPECT_TRUE(rejects(p, up, Vec3(0, 0, 0.2), up, 0.5, params));
  EXPECT_FALSE(rejects(p, up, Vec3(0.2, 0, 0), down, 0.5, params));
  params.criterion = Criterion::Sphere;
  EXPECT_TRUE(rejects(p, up, Vec3(0.2, 0, 0), down, 0.5, params));
}

// --- Distortion (Sorkine) --------------------------------------------------

TEST(Distortion, KnownAffineMaps) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0.3, 0.8, 0);
  const RestTriangle rest = rest_shape(a, b, c);
  EXPECT_NEAR(triangle_distortion(rest, a, b, c), 1.0, 1e-12);
  // A rigid motion in 3D is still an isometry.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  EXPECT_NEAR(triangle_distortion(rest, R * a + Vec3(5, 1, 2), R * b + Vec3(5, 1, 2), R * c + Vec3(5, 1, 2)), 1.0,
              1e-12);
  const Eigen::Matrix3d stretch = Vec3(2, 1, 1).asDiagonal();
  EXPECT_NEAR(triangle_distortion(rest, stretch * a, stretch * b, stretch * c), 2.0, 1e-12);
  const Eigen::Matrix3d shrink = Vec3(1, 0.5, 1).asDiagonal();
  EXPECT_NEAR(triangle_distortion(rest, shrink * a, shrink * b, shrink * c), 2.0, 1e-12);
  EXPECT_TRUE(std::isinf(triangle_distortion(rest, a, b, a)));  // collapsed
  EXPECT_DOUBLE_EQ(triangle_quality(1.0, 3.0), 1.0);
  EXPECT_DOUBLE_EQ(triangle_quality(2.0, 3.0), 0.5);
  EXPECT_DOUBLE_EQ(triangle_quality(4.0, 3.0), 0.0);
}

// --- Fading: Eq. 5 and Eq. 6 ------------------------------------------------

TEST(Fading, FlowFadesWithinTheTimeTheFlowCarriesAPatchOneRadius) {
  // τ = 10, ρ = 0 (Eq. 6: 0.1 per frame); a centre moving 0.25 d per frame
  // fades in 4 frames, one moving 0.05 d per frame at Eq. 6's pace.
  auto frames = [](DiskState s, double motion) {
    double kt = s == DiskState::FadingIn ? 0.0 : 1.0;
    for (int n = 1;; ++n) {
      const FadeResult r = fade_step(s, kt, 0, 10, Fading::Flow, motion);
      if (r.remove || r.state == DiskState::Active) return n;
      kt = r.kt;
    }
  };
  EXPECT_EQ(frames(DiskState::FadingIn, 0.25), 4);
  EXPECT_EQ(frames(DiskState::FadingOutDistorted, 0.25), 4);
  EXPECT_EQ(frames(DiskState::FadingIn, 0.05), 10);
  EXPECT_EQ(frames(DiskState::FadingOutClose, 0.0), 10);
}

TEST(Fading, DensityFadesFasterAndRemovesAtZero) {
  // Fade-in over τ = 10 frames with ρ = 0: 10 steps; with ρ = 4: 2 steps.
  auto frames_to_active = [](int rho, Fading fading) {
    DiskState s = DiskState::FadingIn;
    double kt = 0.0;
    int n = 0;
    while (s == DiskState::FadingIn) {
      const FadeResult r = fade_step(s, kt, rho, 10, fading);
      s = r.state, kt = r.kt, ++n;
    }
    EXPECT_DOUBLE_EQ(kt, 1.0);
    return n;
  };
  EXPECT_EQ(frames_to_active(0, Fading::Density), 10);
  EXPECT_EQ(frames_to_active(4, Fading::Density), 2);
  EXPECT_EQ(frames_to_active(4, Fading::Linear), 10);  // Eq. 5 ignores ρ
  EXPECT_EQ(frames_to_active(4, Fading::Flow), 2);     // still liquid: Eq. 6
  // Eq. 6 fade-out: 1 − (t − t_k)(ρ + 1)/τ.
  FadeResult r = fade_step(DiskState::FadingOutClose, 1.0, 1, 10, Fading::Density);
  EXPECT_NEAR(r.kt, 0.8, 1e-12);
  EXPECT_FALSE(r.remove);
  // A very large ρ would make K_t negative: removed at once.
  r = fade_step(DiskState::FadingOutDistorted, 1.0, 50, 10, Fading::Density);
  EXPECT_TRUE(r.remove);
  r = fade_step(DiskState::FadingOutClose, 0.1, 0, 10, Fading::Density);
  EXPECT_TRUE(r.remove);  // reaches exactly 0
  r = fade_step(DiskState::Active, 1.0, 7, 10, Fading::Density);
  EXPECT_EQ(r.state, DiskState::Active);
  EXPECT_DOUBLE_EQ(r.kt, 1.0);
}

TEST(Fading, AFloorOnTheRateShortensTheFadeButNeverSlowsIt) {
  // The sink rule's floor (a sunk patch goes as fast as its surface): K_t
  // falls by the larger of Eq. 6's rate and the floor.
  FadeResult r = fade_step(DiskState::FadingOutClose, 1.0, 0, 10, Fading::Flow, 0.0, 0.35);
  EXPECT_NEAR(r.kt, 0.65, 1e-12);
  r = fade_step(DiskState::FadingOutClose, 1.0, 4, 10, Fading::Flow, 0.0, 0.35);
  EXPECT_NEAR(r.kt, 0.5, 1e-12);  // Eq. 6's (ρ + 1)/τ is faster
  r = fade_step(DiskState::FadingOutClose, 0.3, 0, 10, Fading::Flow, 0.0, 0.35);
  EXPECT_TRUE(r.remove);
}

// --- Patches: LSCM, Eq. 4 -----------------------------------------------------

SurfaceSample sample_near(const SurfaceIndex& s, const Vec3& p) {
  SurfaceSample out;
  out.point = s.closest_point(p);
  out.normal = s.normal_at(out.point);
  return out;
}

TEST(Patch, BoundaryEdgeBitsMarkTheEdgesNoOtherTriangleUses) {
  // A fan of four around vertex 0, two more triangles on its edge 1-2 (a
  // non-manifold edge of three triangles: not a boundary edge), and a loose
  // triangle with its vertices numbered downwards.
  const std::vector<Tri> triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}, {2, 1, 5}, {1, 2, 6}, {9, 8, 7}};
  std::vector<std::uint8_t> expected(triangles.size(), 0);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int a = triangles[t][k], b = triangles[t][(k + 1) % 3];
      int uses = 0;
      for (const Tri& o : triangles) {
        for (int j = 0; j < 3; ++j) uses += std::minmax(a, b) == std::minmax(o[j], o[(j + 1) % 3]);
      }
      if (uses == 1) expected[t] |= static_cast<std::uint8_t>(1u << k);
    }
  }
  EXPECT_EQ(boundary_edge_bits(triangles), expected);
  // Spelled out: the fan's rim edges 2-3, 3-4, 4-1 (1-2 has three triangles).
  EXPECT_EQ(expected[0], 0);
  EXPECT_EQ(expected[1], 0b010);
  EXPECT_EQ(expected[6], 0b111);
  EXPECT_TRUE(boundary_edge_bits({}).empty());
}

TEST(PatchBuilder, FlatGridPatchIsUndistortedAndMetric) {
  const FrameMesh mesh = test::flat_grid(40);
  const SurfaceIndex surface(mesh);
  TrackingOptions o;
  o = o.resolved(1.0);
  o.radius = 0.15;
  std::string why;
  const auto patch = build_patch(surface, sample_near(surface, Vec3(0.52, 0.47, 0)), o, 7, 1, 1, 0.0, &why);
  ASSERT_TRUE(patch) << why;
  EXPECT_EQ(patch->id, 7u);
  double area3 = 0, area_uv = 0;
  for (std::size_t t = 0; t < patch->triangles.size(); ++t) {
    const Tri& tri = patch->triangles[t];
    area3 += 0.5 * (patch->positions[tri[1]] - patch->positions[tri[0]])
                       .cross(patch->positions[tri[2]] - patch->positions[tri[0]])
                       .norm();
    const Vec2 e1 = patch->uvs[tri[1]] - patch->uvs[tri[0]], e2 = patch->uvs[tri[2]] - patch->uvs[tri[0]];
    area_uv += 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
    // uv is an isometry of a flat patch: uv distances equal 3D distances.
    EXPECT_NEAR((patch->uvs[tri[1]] - patch->uvs[tri[0]]).norm(),
                (patch->positions[tri[1]] - patch->positions[tri[0]]).norm(), 1e-6);
  }
  EXPECT_NEAR(area_uv, area3, 1e-9 * area3);
  // Every vertex within the selection radius (plus one grid diagonal: a
  // triangle reaching into the ball is taken whole), the centre at uv 0.
  double farthest = 0.0;
  for (std::size_t v = 0; v < patch->num_vertices(); ++v) {
    farthest = std::max(farthest, (patch->positions[v] - Vec3(0.52, 0.47, 0)).norm());
    EXPECT_LE((patch->positions[v] - Vec3(0.52, 0.47, 0)).norm(), 1.6 * 0.15 + std::sqrt(2.0) / 40 + 1e-9);
    EXPECT_NEAR(patch->uvs[v].norm(), (patch->positions[v] - Vec3(0.52, 0.47, 0)).norm(), 1e-6);
  }
  EXPECT_GT(farthest, 1.6 * 0.15 - std::sqrt(2.0) / 40);  // and it reaches out that far
  Patch p = *patch;
  EXPECT_EQ(update_distortion(p, surface, o), RetireCause::None);
  EXPECT_NEAR(p.max_distortion, 1.0, 1e-6);
  // A disk-sized patch reaches beyond d, with a border.
  int border = 0;
  for (auto b : p.border) border += b;
  EXPECT_GT(border, 10);
  EXPECT_GT(p.num_vertices(), 100u);
  EXPECT_GE(p.anchor.x(), 0.0);
  EXPECT_LT(p.anchor.x(), 1.0);
}

TEST(PatchBuilder, SelectionStaysADiskAroundAHole) {
  // A grid with a hole of one quad near the centre: the patch must stay a
  // topological disk (one boundary loop) so LSCM applies.
  FrameMesh mesh = test::flat_grid(20);
  std::vector<Tri> kept;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (t != 2 * (10 * 20 + 11) && t != 2 * (10 * 20 + 11) + 1) kept.push_back(mesh.triangles[t]);
  }
  mesh.triangles = kept;
  const SurfaceIndex surface(mesh);
  TrackingOptions o = TrackingOptions{}.resolved(1.0);
  o.radius = 0.2;
  const auto patch = build_patch(surface, sample_near(surface, Vec3(0.5, 0.5, 0)), o, 0, 1, 1, 0.0);
  ASSERT_TRUE(patch);
  // Euler characteristic of a disk: V − E + F = 1.
  std::set<std::pair<int, int>> edges;
  for (const Tri& t : patch->triangles) {
    for (int k = 0; k < 3; ++k) edges.insert({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
  }
  EXPECT_EQ(static_cast<long>(patch->num_vertices()) - static_cast<long>(edges.size()) +
                static_cast<long>(patch->triangles.size()),
            1);
}

TEST(Weights, Eq4SpatialTimesTemporal) {
  Patch p;
  p.positions.assign(4, Vec3::Zero());
  p.uvs = {Vec2(0, 0), Vec2(0.05, 0), Vec2(0.0, 0.2), Vec2(0.03, 0.04)};
  p.border = {0, 0, 0, 1};
  p.quality = {1.0f, 0.5f, 1.0f, 1.0f};
  p.kt = 0.5;
  TrackingOptions o;
  o.radius = 0.1;
  o.uv_scale = 1.0;
  o.selection_margin = 0.6;
  update_weights(p, o);
  // Eq. 4 plus the coverage tail ε·(1 − r/((1 + β)d)), (1 + β)d = 0.16.
  const double eps = kCoverageTail;
  EXPECT_NEAR(p.weight[0], (1 + eps) * 0.5, 1e-7);                                    // centre: K_S = 1
  EXPECT_NEAR(p.weight[1], ((1 - 0.5) + eps * (1 - 0.05 / 0.16)) * 0.5 * 0.5, 1e-7);  // half way, Q_V = 0.5
  EXPECT_EQ(p.weight[2], 0.0f);                                                       // beyond (1 + β)d
  // Border: d_V = 0 takes the disk's term; the tail stays, so that a patch
  // the plane test cut short still covers its own surface.
  EXPECT_NEAR(p.weight[3], eps * (1 - 0.05 / 0.16) * 0.5, 1e-7);
  EXPECT_EQ(core_weight(p, 3, o.radius.value(), o.uv_scale), 0.0f);  // Eq. 4 alone
}

// --- Sampling ------------------------------------------------------------------

/// Largest distance from any surface vertex to the nearest disk centre.
double coverage_gap(const FrameMesh& mesh, const std::vector<SurfaceSample>& disks) {
  double worst = 0;
  for (const Vec3& v : mesh.positions) {
    double best = 1e300;
    for (const SurfaceSample& d : disks) best = std::min(best, (d.point.position - v).norm());
    worst = std::max(worst, best);
  }
  return worst;
}

TEST(PoissonSampling, SphereIsMaximalAndRespectsTheCriterion) {
  const FrameMesh mesh = test::uv_sphere(40, 80, 1.0);
  const SurfaceIndex surface(mesh);
  const PoissonParams params{0.3, 0.075, 0.5, Criterion::Ellipsoid};
  const auto candidates = surface_candidates(surface, params.radius, 9);
  const auto disks = fill_gaps({}, candidates, surface, params, 0.0);
  ASSERT_GT(disks.size(), 40u);
  for (std::size_t i = 0; i < disks.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      EXPECT_FALSE(rejects(disks[j].point.position, disks[j].normal, disks[i].point.position, disks[i].normal,
                           params.radius, params));
    }
  }
  // Maximal: no point of the sphere is farther than ~d from a disk.
  EXPECT_LT(coverage_gap(mesh, disks), 1.1 * params.radius);
  // Deterministic for a seed, different for another.
  const auto again = fill_gaps({}, surface_candidates(surface, params.radius, 9), surface, params, 0.0);
  ASSERT_EQ(again.size(), disks.size());
  for (std::size_t i = 0; i < disks.size(); ++i) EXPECT_EQ(again[i].point.position, disks[i].point.position);
  const auto other = fill_gaps({}, surface_candidates(surface, params.radius, 10), surface, params, 0.0);
  EXPECT_NE(other.front().point.position, disks.front().point.position);
}

TEST(PoissonSampling, TwoCloseParallelPlanesAreBothCovered) {
  // Figs. 3 and 5: two surfaces closer than d. The ellipsoid criterion covers
  // both; a plain 3D radius (or plane test + radius) leaves the lower one bare.
  const double d = 0.2;
  FrameMesh mesh = test::flat_grid(40, 1.0, 0.0);
  test::append(mesh, test::flat_grid(40, 1.0, 0.5 * d));
  const SurfaceIndex surface(mesh);
  FrameMesh lower = test::flat_grid(40, 1.0, 0.0);
  FrameMesh upper = test::flat_grid(40, 1.0, 0.5 * d);
  auto gaps = [&](Criterion c) {
    const PoissonParams params{d, 0.25 * d, 0.5, c};
    const auto disks = fill_gaps({}, surface_candidates(surface, d, 3), surface, params, 0.0);
    std::vector<SurfaceSample> on_lower, on_upper;
    for (const auto& s : disks) (s.point.position.z() < 0.25 * d ? on_lower : on_upper).push_back(s);
    return std::make_pair(coverage_gap(lower, on_lower), coverage_gap(upper, on_upper));
  };
  const auto ellipsoid = gaps(Criterion::Ellipsoid);
  EXPECT_LT(ellipsoid.first, 1.1 * d);
  EXPECT_LT(ellipsoid.second, 1.1 * d);
  const auto sphere = gaps(Criterion::Sphere);
  EXPECT_GT(std::max(sphere.first, sphere.second), 1.3 * d);
  const auto plane = gaps(Criterion::Plane);
  EXPECT_GT(std::max(plane.first, plane.second), 1.3 * d);
}

TEST(PoissonSampling, TheBirthMarginKeepsNewDisksFartherFromOldOnes) {
  // Half a plane keeps its disks; the other half is a gap to fill. With the
  // margin γ new disks keep (1 + γ)·d from the old ones, d from each other,
  // and still leave no point farther than about (1 + γ)·d from a disk.
  const double d = 0.1;
  const FrameMesh mesh = test::flat_grid(60, 1.0);
  const SurfaceIndex surface(mesh);
  const PoissonParams params{d, 0.25 * d, 0.5, Criterion::Ellipsoid};
  const auto candidates = surface_candidates(surface, d, 4);
  std::vector<SurfaceSample> old;
  for (const SurfaceSample& s : fill_gaps({}, candidates, surface, params, 0.0)) {
    if (s.point.position.x() < 0.5) old.push_back(s);
  }
  auto nearest_old = [&](const std::vector<SurfaceSample>& fresh) {
    double nearest = 1e300;
    for (const SurfaceSample& f : fresh) {
      for (const SurfaceSample& o : old) nearest = std::min(nearest, (f.point.position - o.point.position).norm());
    }
    return nearest;
  };
  const auto paper = fill_gaps(old, candidates, surface, params, 0.0);
  ASSERT_GT(paper.size(), 10u);
  EXPECT_GE(nearest_old(paper), d);
  EXPECT_LT(nearest_old(paper), 1.3 * d);  // the margin below must change something
  for (const double margin : {0.3, 0.6}) {
    const auto fresh = fill_gaps(old, candidates, surface, params, 0.0, nullptr, margin);
    ASSERT_GT(fresh.size(), 10u);
    EXPECT_GE(nearest_old(fresh), (1.0 + margin) * d);
    for (std::size_t i = 0; i < fresh.size(); ++i) {
      for (std::size_t j = 0; j < i; ++j) EXPECT_GE((fresh[i].point.position - fresh[j].point.position).norm(), d);
    }
    std::vector<SurfaceSample> all = old;
    all.insert(all.end(), fresh.begin(), fresh.end());
    EXPECT_LT(coverage_gap(mesh, all), 1.1 * (1.0 + margin) * d);
  }
}

TEST(PoissonSampling, SmallComponentsGetADisk) {
  FrameMesh mesh = test::flat_grid(30, 1.0);
  test::append(mesh, test::uv_sphere(6, 8, 0.02, Vec3(0.5, 0.5, 0.03)));  // a droplet just above
  const SurfaceIndex surface(mesh);
  ASSERT_EQ(surface.num_components(), 2);
  const PoissonParams params{0.2, 0.05, 0.5, Criterion::Sphere};  // the sphere criterion would miss it
  const auto disks = fill_gaps({}, surface_candidates(surface, 0.2, 1), surface, params, 1e-4);
  int on_droplet = 0;
  for (const auto& s : disks) on_droplet += surface.face_component()[s.point.face] == 1;
  EXPECT_GE(on_droplet, 1);
}

TEST(PoissonSampling, KillDistanceFlagsTheYoungerDisk) {
  const PoissonParams params{0.2, 0.05, 0.5, Criterion::Ellipsoid};
  auto at = [](double x) {
    SurfaceSample s;
    s.point.position = Vec3(x, 0, 0);
    s.normal = Vec3::UnitZ();
    return s;
  };
  // Kill distance (1 − 0.25)·0.2 = 0.15.
  const auto flags = flag_too_close({at(0.0), at(0.1), at(0.26), at(0.5)}, params, 0.25);
  EXPECT_EQ(flags, (std::vector<bool>{false, true, false, false}));
  EXPECT_EQ(flag_too_close({at(0.0), at(0.16)}, params, 0.25), (std::vector<bool>{false, false}));
}

// --- Tracker ---------------------------------------------------------------------

std::shared_ptr<FrameMesh> rotating_grid(double omega) {
  return std::make_shared<FrameMesh>(test::flat_grid(
      40, 1.0, 0.0, -0.5, -0.5, [omega](const Vec3& p) { return Vec3(-omega * p.y(), omega * p.x(), 0); }));
}

TrackerSettings small_settings() {
  TrackerSettings s;
  s.method.radius = 0.12;
  s.method.fade_frames = 8;
  s.seed = 5;
  return s;
}

TEST(Tracker, ZeroVelocityKeepsTheFirstDistribution) {
  Tracker t(small_settings());
  const StepReport first = t.step(rotating_grid(0.0), 1, 1.0 / 24);
  EXPECT_GT(first.created, 10);
  EXPECT_EQ(first.counts.active, first.created);
  for (int f = 2; f <= 5; ++f) {
    const StepReport r = t.step(rotating_grid(0.0), f, 1.0 / 24);
    EXPECT_EQ(r.created, 0);
    EXPECT_EQ(r.removed, 0);
    EXPECT_EQ(r.counts.active, first.created);
  }
  for (const Patch& p : t.patches()) {
    EXPECT_NEAR(p.max_distortion, 1.0, 1e-6);
    EXPECT_EQ(p.kt, 1.0);
  }
}

// --- Advection schemes ------------------------------------------------------

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

TEST(Tracker, ConstantVelocityTranslatesPatchesExactly) {
  // A large plane translating: patch vertices move by exactly v·dt.
  const Vec3 v(0.3, -0.12, 0);
  auto plane = [&]() {
    return std::make_shared<FrameMesh>(test::flat_grid(30, 3.0, 0.0, -1.5, -1.5, [&](const Vec3&) { return v; }));
  };
  TrackerSettings s = small_settings();
  s.method.radius = 0.3;
  // The window is fixed: the strip the liquid bares at its upstream edge
  // would be covered by recutting the patches next to it.
  s.method.gap_fill = GapFill::Seed;
  Tracker t(s);
  t.step(plane(), 1, 0.1);
  const Patch before = t.patches().front();
  t.step(plane(), 2, 0.1);
  const Patch& after = t.patches().front();
  ASSERT_EQ(after.id, before.id);
  EXPECT_NEAR((after.centre.point.position - before.centre.point.position - 0.1 * v).norm(), 0.0, 1e-12);
  ASSERT_EQ(after.num_vertices(), before.num_vertices());
  for (std::size_t i = 0; i < after.num_vertices(); ++i) {
    EXPECT_NEAR((after.positions[i] - before.positions[i] - 0.1 * v).norm(), 0.0, 1e-12);
  }
  EXPECT_NEAR(after.max_distortion, 1.0, 1e-9);
}

TEST(Tracker, RotationGoesThroughTheStates) {
  // The paper's states: a distorted patch fades out rather than being recut.
  TrackerSettings s = small_settings();
  s.method.distorted = Distorted::Fade;
  Tracker t(s);
  bool saw_fading_in = false, saw_close = false, saw_distorted = false;
  int removed = 0;
  for (int f = 1; f <= 40; ++f) {
    const StepReport r = t.step(rotating_grid(1.5), f, 1.0 / 24);
    saw_fading_in |= r.counts.fading_in > 0;
    saw_close |= r.counts.fading_out_close > 0;
    saw_distorted |= r.counts.fading_out_distorted > 0;
    removed += r.removed;
    for (const Patch& p : t.patches()) {
      EXPECT_GE(p.kt, 0.0);
      EXPECT_LE(p.kt, 1.0);
      if (p.state == DiskState::Active) EXPECT_EQ(p.kt, 1.0);
    }
  }
  EXPECT_TRUE(saw_fading_in);
  EXPECT_TRUE(saw_close || saw_distorted);
  EXPECT_GT(removed, 0);
}

/// Share of the tracker's current surface that no patch covers, tested at
/// points `spacing` apart.
double uncovered_area(const Tracker& t, double spacing) {
  const PatchCoverage coverage(t.patches(), t.settings().method.mpt());
  return uncovered_area_fraction(*t.surface(), coverage, spacing);
}

TEST(Tracker, GeneratedScenesGoThroughTheStatesAndStayCovered) {
  // The rotation keeps its patches; the drop, through its contact (frame ~6
  // of 12), replaces some: patches fade in, fade out and are removed, and
  // K_t follows Eq. 6 (the paper's states: distorted patches fade out).
  SceneOptions so;
  so.resolution = 20;
  so.frames = 12;
  for (const char* scene : {"rotation", "drop"}) {
    SCOPED_TRACE(scene);
    TrackerSettings s;
    s.method.distorted = Distorted::Fade;
    Tracker t(s);
    int created_later = 0, removed = 0, fading_out = 0;
    for (int f = 1; f <= so.frames; ++f) {
      const StepReport r = t.step(std::make_shared<FrameMesh>(make_scene_frame(scene, f, so)), f, 1.0 / so.fps);
      if (f > 1) created_later += r.created;
      removed += r.removed;
      fading_out += r.counts.fading_out_distorted + r.counts.fading_out_close;
      for (const Patch& p : t.patches()) {
        ASSERT_GE(p.kt, 0.0);
        ASSERT_LE(p.kt, 1.0);
        if (p.state == DiskState::Active) ASSERT_EQ(p.kt, 1.0);
        if (p.state == DiskState::FadingIn) ASSERT_LT(p.kt, 1.0);
      }
      EXPECT_LT(uncovered_area(t, t.coverage_spacing()), 1e-3) << "frame " << f;
    }
    if (std::string(scene) == "rotation") {
      EXPECT_EQ(removed, 0);
    } else {
      EXPECT_GT(created_later, 0);
      EXPECT_GT(fading_out, 0);
      EXPECT_GT(removed, 0);
    }
  }
}

/// Droplets smaller than the disk, as splashes shed them: a pool with three
/// coarse blobs of radius 0.1–0.3 d above it. The plane test cuts a patch on
/// such a blob down to a few triangles whose vertices all lie on its border
/// (d_V = 0: Eq. 4 gives it no weight anywhere); its coverage tail must still
/// cover the blob, whatever the frame.
TEST(Tracker, DropletsSmallerThanTheDiskAreCovered) {
  FrameMesh mesh = test::flat_grid(24, 4.0);
  test::append(mesh, test::uv_sphere(3, 5, 0.1, Vec3(1.0, 1.0, 0.5)));
  test::append(mesh, test::uv_sphere(4, 6, 0.2, Vec3(2.0, 2.5, 0.6)));
  test::append(mesh, test::uv_sphere(3, 4, 0.3, Vec3(3.0, 1.2, 0.8)));
  TrackerSettings settings;
  settings.method.radius = 1.0;
  Tracker t(settings);
  for (int f = 1; f <= 3; ++f) {
    t.step(std::make_shared<FrameMesh>(mesh), f, 1.0 / 24.0);
    EXPECT_EQ(uncovered_area(t, t.coverage_spacing()), 0.0) << "frame " << f;
  }
}

/// Faces several disks wide (a coarse cache, or a wall of the tank meshed
/// with a few large triangles): coverage is tested at points d/4 apart
/// (kCoverageSpacing), so no bare sliver hides inside a face whose centre is covered. At
/// half that spacing, gaps narrower than the samples may show (synthesis
/// gives them a patch's margin), a tiny share of the area.
TEST(Tracker, CoarseFacesAreCoveredInside) {
  const FrameMesh mesh =
      test::flat_grid(3, 3.0, 0.0, 0.0, 0.0, [](const Vec3& p) { return Vec3(0.3 * p.y(), 0.0, 0.0); });
  TrackerSettings settings;
  settings.method.radius = 0.25;
  Tracker t(settings);
  for (int f = 1; f <= 4; ++f) {
    t.step(std::make_shared<FrameMesh>(mesh), f, 1.0 / 24.0);
    EXPECT_EQ(uncovered_area(t, t.coverage_spacing()), 0.0) << "frame " << f;
    EXPECT_LT(uncovered_area(t, 0.5 * t.coverage_spacing()), 2e-4) << "frame " << f;
  }
}

std::string run_and_save(int threads, const std::string& path) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  Tracker t(small_settings());
  for (int f = 1; f <= 12; ++f) t.step(rotating_grid(1.5), f, 1.0 / 24);
  t.save(path);
  return test::read_file(path);
}

TEST(Tracker, IdenticalForAnyThreadCount) {
  test::TempDir dir;
  const std::string one = run_and_save(1, dir.file("a.bin"));
  const std::string two = run_and_save(2, dir.file("b.bin"));
  EXPECT_GT(one.size(), 1000u);
  EXPECT_TRUE(one == two);
}

TEST(Tracker, StateRoundTripContinuesExactly) {
  test::TempDir dir;
  Tracker a(small_settings());
  std::shared_ptr<FrameMesh> mesh;
  for (int f = 1; f <= 6; ++f) a.step(mesh = rotating_grid(1.5), f, 1.0 / 24);
  a.save(dir.file("s6.bin"));
  Tracker b = Tracker::load(dir.file("s6.bin"), rotating_grid(1.5));
  b.save(dir.file("s6b.bin"));
  EXPECT_EQ(test::read_file(dir.file("s6.bin")), test::read_file(dir.file("s6b.bin")));
  EXPECT_EQ(b.frame(), 6);
  for (int f = 7; f <= 9; ++f) {
    a.step(rotating_grid(1.5), f, 1.0 / 24);
    b.step(rotating_grid(1.5), f, 1.0 / 24);
  }
  a.save(dir.file("a9.bin"));
  b.save(dir.file("b9.bin"));
  EXPECT_EQ(test::read_file(dir.file("a9.bin")), test::read_file(dir.file("b9.bin")));
}

TEST(Tracker, StateFileErrors) {
  test::TempDir dir;
  Tracker a(small_settings());
  a.step(rotating_grid(1.0), 1, 1.0 / 24);
  a.save(dir.file("s.bin"));
  EXPECT_THROW(Tracker::load(dir.file("s.bin"), rotating_grid(2.0)), InputError);  // other velocities
  const std::string bytes = test::read_file(dir.file("s.bin"));
  // Cut anywhere, or one byte damaged anywhere (the checksum catches what
  // the structure does not): refused, never loaded, never a crash.
  for (std::size_t at = 0; at < bytes.size(); at += std::max<std::size_t>(1, bytes.size() / 61)) {
    test::write_file(dir.path() / "t.bin", bytes.substr(0, at));
    EXPECT_THROW(Tracker::load(dir.file("t.bin"), rotating_grid(1.0)), InputError) << "cut at " << at;
    std::string bad = bytes;
    bad[at] = static_cast<char>(bad[at] ^ 0x5a);
    test::write_file(dir.path() / "e.bin", bad);
    EXPECT_THROW(Tracker::load(dir.file("e.bin"), rotating_grid(1.0)), InputError) << "flip at " << at;
  }
  test::write_file(dir.path() / "x.bin", bytes + "x");
  EXPECT_THROW(Tracker::load(dir.file("x.bin"), rotating_grid(1.0)), InputError);
  test::write_file(dir.path() / "u.bin", "hello");
  EXPECT_THROW(Tracker::load(dir.file("u.bin"), rotating_grid(1.0)), InputError);
  EXPECT_THROW(Tracker::load(dir.file("missing.bin"), rotating_grid(1.0)), InputError);
}

/// Whether two lists hold the same hits (patch, triangle, barycentric
/// coordinates, uv and weight) in the same order.
::testing::AssertionResult same_hits(const std::vector<PatchHit>& a, const std::vector<PatchHit>& b) {
  if (a.size() != b.size()) return ::testing::AssertionFailure() << a.size() << " hits against " << b.size();
  for (std::size_t h = 0; h < a.size(); ++h) {
    if (a[h].patch != b[h].patch || a[h].tri != b[h].tri || a[h].bary != b[h].bary || a[h].uv != b[h].uv ||
        a[h].weight != b[h].weight)
      return ::testing::AssertionFailure()
             << "hit " << h << " differs (patch " << a[h].patch << " against " << b[h].patch << ")";
  }
  return ::testing::AssertionSuccess();
}

TEST(PatchCoverage, AgreesWithTheExactLocator) {
  // The cheap coverage test must give the locator's answer (some hit with
  // w > 0) everywhere, including near patch rims and fading patches.
  SceneOptions so;
  so.resolution = 20;
  so.frames = 12;
  Tracker t(TrackerSettings{});
  for (int f = 1; f <= 8; ++f) t.step(std::make_shared<FrameMesh>(make_scene_frame("drop", f, so)), f, 1.0 / so.fps);
  const double tol = t.settings().method.mpt();
  // Every other patch only, so that some points are bare.
  std::vector<char> half(t.patches().size(), 0);
  for (std::size_t i = 0; i < half.size(); i += 2) half[i] = 1;
  const PatchLocator locator(t.patches(), tol, &half);
  const PatchCoverage coverage(t.patches(), tol, &half);
  const SurfaceIndex& surface = *t.surface();
  std::vector<PatchHit> hits, found;
  // locate_each's hits for a group of points are locate()'s for each.
  auto locate_each_agrees = [&](const std::vector<Vec3>& points, const std::vector<Vec3>& normals) {
    std::size_t calls = 0;
    coverage.locate_each(points, normals, [&](std::size_t i, std::vector<PatchHit>& each) {
      ASSERT_EQ(i, calls++);
      std::vector<PatchHit> one;
      coverage.locate(points[i], normals[i], one);
      ASSERT_TRUE(same_hits(each, one)) << "point " << i;
    });
    ASSERT_EQ(calls, points.size());
  };
  std::vector<Vec3> all_points, all_normals;
  int covered = 0, bare = 0;
  for (std::size_t f = 0; f < surface.mesh().triangles.size(); ++f) {
    std::vector<Vec3> points, normals;
    for (const Vec3& b :
         {Vec3(Vec3::Constant(1.0 / 3.0)), Vec3(0.8, 0.1, 0.1), Vec3(0.05, 0.05, 0.9), Vec3(0.5, 0.5, 0.0)}) {
      const SurfacePoint s = surface.at(static_cast<int>(f), b);
      const Vec3 n = surface.normal_at(s);
      locator.locate(s.position, n, hits);
      const bool expected = std::any_of(hits.begin(), hits.end(), [](const PatchHit& h) { return h.weight > 0.0; });
      ASSERT_EQ(coverage.covers(s.position, n), expected) << "face " << f;
      (expected ? covered : bare)++;
      // The same hits without a triangle tree.
      coverage.locate(s.position, n, found);
      ASSERT_TRUE(same_hits(found, hits)) << "face " << f;
      points.push_back(s.position);
      normals.push_back(n);
    }
    // One face's points as a group: the bare ones, as covers() one by one.
    std::vector<std::size_t> reported;
    coverage.uncovered_each(points, normals, {0, points.size()}, [&](std::size_t g, std::size_t i) {
      EXPECT_EQ(g, 0u);
      reported.push_back(i);
    });
    std::vector<std::size_t> expected_bare;
    for (std::size_t i = 0; i < points.size(); ++i)
      if (!coverage.covers(points[i], normals[i])) expected_bare.push_back(i);
    ASSERT_EQ(reported, expected_bare) << "face " << f;
    locate_each_agrees(points, normals);
    all_points.insert(all_points.end(), points.begin(), points.end());
    all_normals.insert(all_normals.end(), normals.begin(), normals.end());
  }
  // Samples of many faces in shuffled order (the dart-throwing candidates):
  // bare exactly where covers() says so.
  std::vector<SurfaceSample> samples;
  for (std::size_t k = 0; k < all_points.size(); ++k) {
    const std::size_t i = (k * 7919) % all_points.size();
    SurfaceSample sample;
    sample.point = surface.closest_point(all_points[i]);
    sample.point.position = all_points[i];
    sample.normal = all_normals[i];
    samples.push_back(sample);
  }
  const std::vector<char> uncovered = uncovered_samples(samples, coverage);
  ASSERT_EQ(uncovered.size(), samples.size());
  for (std::size_t k = 0; k < samples.size(); ++k)
    ASSERT_EQ(uncovered[k] != 0, !coverage.covers(samples[k].point.position, samples[k].normal)) << "sample " << k;
  // Every face's samples at once: each bare face with its first bare sample.
  const FaceSamples fs = face_samples(surface, 0.3 * t.settings().method.d());
  const BareFaces found_bare = bare_faces(surface, fs, coverage);
  std::size_t next = 0;
  for (std::size_t f = 0; f < surface.mesh().triangles.size(); ++f) {
    std::ptrdiff_t first = -1;
    for (std::size_t k = fs.start[f]; k < fs.start[f + 1] && first < 0; ++k) {
      const SurfacePoint sp = surface.at(static_cast<int>(f), fs.bary[k]);
      if (!coverage.covers(sp.position, surface.normal_at(sp))) first = static_cast<std::ptrdiff_t>(k);
    }
    if (first < 0) continue;
    ASSERT_LT(next, found_bare.face.size()) << "face " << f;
    ASSERT_EQ(found_bare.face[next], static_cast<int>(f));
    ASSERT_EQ(found_bare.point[next].point.position,
              surface.at(static_cast<int>(f), fs.bary[static_cast<std::size_t>(first)]).position)
        << "face " << f;
    ++next;
  }
  ASSERT_EQ(next, found_bare.face.size());
  // Groups spread over many faces, as a tile's texels over several charts.
  for (std::size_t first = 0; first < all_points.size(); first += 97) {
    const std::size_t last = std::min(all_points.size(), first + 97);
    locate_each_agrees({all_points.begin() + first, all_points.begin() + last},
                       {all_normals.begin() + first, all_normals.begin() + last});
  }
  EXPECT_GT(covered, 1000);
  EXPECT_GT(bare, 100);
  // With no patch nothing is covered.
  const std::vector<Patch> none;
  EXPECT_FALSE(PatchCoverage(none, tol).covers(Vec3::Zero(), Vec3::UnitZ()));
  int bare_calls = 0;
  PatchCoverage(none, tol).uncovered_each({Vec3::Zero()}, {Vec3::UnitZ()}, {0, 1},
                                          [&](std::size_t, std::size_t) { ++bare_calls; });
  EXPECT_EQ(bare_calls, 1);
  int empty_calls = 0;
  PatchCoverage(none, tol).locate_each({Vec3::Zero(), Vec3::UnitX()}, {Vec3::UnitZ(), Vec3::UnitZ()},
                                       [&](std::size_t, std::vector<PatchHit>& each) {
                                         EXPECT_TRUE(each.empty());
                                         ++empty_calls;
                                       });
  EXPECT_EQ(empty_calls, 2);
}

TEST(PatchCoverage, NearestFindsTheClosestFacingPatchPoint) {
  // One patch: the unit square at z = 0, facing +z, split in two triangles.
  std::vector<Patch> patches(1);
  Patch& p = patches[0];
  p.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  p.uvs = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
  p.weight = {1.0, 1.0, 1.0, 1.0};
  p.triangles = {Tri{0, 1, 2}, Tri{0, 2, 3}};
  const PatchCoverage coverage(patches, 0.1);
  PatchHit hit;
  // Beside the square, in its plane: the nearest point of its edge.
  ASSERT_TRUE(coverage.nearest(Vec3(1.05, 0.5, 0.0), Vec3::UnitZ(), 0.1, hit));
  EXPECT_EQ(hit.patch, 0);
  EXPECT_NEAR(hit.uv.x(), 1.0, 1e-12);
  EXPECT_NEAR(hit.uv.y(), 0.5, 1e-12);
  // Out of reach, or seen from the back: nothing.
  EXPECT_FALSE(coverage.nearest(Vec3(1.2, 0.5, 0.0), Vec3::UnitZ(), 0.1, hit));
  EXPECT_FALSE(coverage.nearest(Vec3(1.05, 0.5, 0.0), -Vec3::UnitZ(), 0.1, hit));
  // The in-plane gap is what locate() does not reach.
  std::vector<PatchHit> hits;
  coverage.locate(Vec3(1.05, 0.5, 0.0), Vec3::UnitZ(), hits);
  EXPECT_TRUE(hits.empty());
}

TEST(FaceSamples, SubdivideEachFaceDownToTheSpacing) {
  // Two faces: a unit right triangle and one a tenth its size.
  FrameMesh mesh;
  mesh.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(2, 0, 0), Vec3(2.1, 0, 0), Vec3(2, 0.1, 0)};
  mesh.velocities.assign(mesh.positions.size(), Vec3::Zero());
  mesh.triangles = {Tri{0, 1, 2}, Tri{3, 4, 5}};
  const SurfaceIndex surface(mesh);
  const FaceSamples s = face_samples(surface, 0.25);
  // Longest edge √2 over 0.25: 6 steps, 36 samples; the small face: its centroid.
  ASSERT_EQ(s.count, (std::vector<int>{6, 1}));
  ASSERT_EQ(s.start, (std::vector<std::size_t>{0, 36, 37}));
  Vec3 mean = Vec3::Zero();
  std::set<std::pair<long, long>> distinct;
  for (std::size_t i = 0; i < 36; ++i) {
    const Vec3& b = s.bary[i];
    EXPECT_NEAR(b.sum(), 1.0, 1e-12);
    EXPECT_GT(b.minCoeff(), 0.0);  // strictly inside the face
    mean += b;
    distinct.emplace(std::lround(b.y() * 1e9), std::lround(b.z() * 1e9));
  }
  // Sub-triangle centroids of an even subdivision: distinct, and their mean is the face's centroid.
  EXPECT_EQ(distinct.size(), 36u);
  EXPECT_TRUE(mean.isApprox(Vec3::Constant(12.0), 1e-12));
  EXPECT_TRUE(s.bary[36].isApprox(Vec3::Constant(1.0 / 3.0), 1e-12));
  // No spacing: the centroids alone.
  EXPECT_EQ(face_samples(surface, 0.0).count, (std::vector<int>{1, 1}));
}

// Random draws for the tests of one patch triangle against points around it.
struct RandomTriangle {
  explicit RandomTriangle(unsigned seed) : rng(seed) { patch.triangles = {Tri{0, 1, 2}}; }
  double u() { return unit(rng); }  ///< uniform in [−1, 1)
  Vec3 vec() { return Vec3(u(), u(), u()); }
  std::mt19937 rng;
  std::uniform_real_distribution<double> unit{-1.0, 1.0};
  Patch patch;
};

// TrianglePrism::may_cover is a pre-test: it may pass points the full
// projection rejects, never the reverse. Points are drawn around random
// triangles, many of them within a few slacks of an edge, a corner or the
// tolerance, where the two tests are closest.
TEST(TrianglePrism, NeverRejectsWhatTheProjectionCovers) {
  RandomTriangle draw(7);
  Patch& patch = draw.patch;
  int covered = 0, prefiltered = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const double scale = std::pow(10.0, 3.0 * draw.u());
    const Vec3 offset = 100.0 * scale * draw.vec();
    patch.positions = {offset + scale * draw.vec(), offset + scale * draw.vec(), offset + scale * draw.vec()};
    if (trial % 50 == 0) patch.positions[2] = patch.positions[1];  // degenerate
    const double tolerance = scale * 0.2 * (1.0 + draw.u());
    const TrianglePrism prism(patch, patch.triangles[0], tolerance);
    const Vec3 tn = (patch.positions[1] - patch.positions[0]).cross(patch.positions[2] - patch.positions[0]);
    const Vec3 n = tn.squaredNorm() > 0.0 ? tn.normalized() : Vec3::UnitZ();
    for (int k = 0; k < 50; ++k) {
      // A point of the triangle's plane (barycentric coordinates up to a
      // little outside), then lifted along the normal up to about the
      // tolerance.
      Vec3 l(draw.u(), draw.u(), 0.0);
      l.z() = 1.0 - l.x() - l.y();
      if (k % 2) l *= 1.0 + 1e-3 * draw.u();
      const Vec3 p = l.x() * patch.positions[0] + l.y() * patch.positions[1] + l.z() * patch.positions[2];
      const Vec3 q = p + (k % 3 ? 1.0 : 1.0 + 1e-9) * tolerance * draw.u() * n;
      Vec3 bary;
      double dist2;
      const bool full = project_to_patch_triangle(patch, patch.triangles[0], q, n, tolerance, bary, dist2);
      const bool may = prism.may_cover(q);
      ASSERT_TRUE(may || !full) << "trial " << trial << " point " << k;
      // The same tests as half-spaces (the synthesis' row spans), up to rounding.
      std::array<TrianglePrism::HalfSpace, 5> half_spaces;
      bool everything = false;
      if (prism.half_spaces(half_spaces, everything)) {
        const double eps = 1e-9 * (scale + offset.norm());
        bool inside_loose = true, inside_strict = true;
        for (const auto& h : half_spaces) {
          const double v = h.n.dot(q) - h.c;
          inside_loose = inside_loose && v >= -eps;
          inside_strict = inside_strict && v >= eps;
        }
        ASSERT_TRUE(!may || inside_loose) << "trial " << trial << " point " << k;
        ASSERT_TRUE(!inside_strict || may) << "trial " << trial << " point " << k;
      } else {
        ASSERT_EQ(may, everything) << "trial " << trial;
      }
      covered += full;
      prefiltered += !may;
    }
  }
  // Both outcomes occur often enough for the check to mean something.
  EXPECT_GT(covered, 5000);
  EXPECT_GT(prefiltered, 20000);
}

// project_to_patch_triangle against its definition, the slack test by the
// closest point of the triangle for every point outside it (project() skips
// that search where an edge's line alone puts the point beyond the slack).
// Points are drawn in a band of a few slacks around random triangles, where
// both answers occur.
TEST(TriangleProjection, CoversWhatItsClosestPointPutsWithinTheSlack) {
  RandomTriangle draw(5);
  Patch& patch = draw.patch;
  int inside = 0, in_slack = 0, beyond = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    const double scale = std::pow(10.0, 2.0 * draw.u());
    patch.positions = {scale * draw.vec(), scale * draw.vec(), scale * draw.vec()};
    if (trial % 3 == 0)
      patch.positions[2] =
          patch.positions[0] + 0.02 * scale * draw.vec() + 0.5 * (patch.positions[1] - patch.positions[0]);  // a sliver
    const double tolerance = scale * 0.3 * (1.5 + draw.u());
    const double slack = projection_slack(tolerance);
    const Vec3& a = patch.positions[0];
    const Vec3& b = patch.positions[1];
    const Vec3& c = patch.positions[2];
    const Vec3 n = (b - a).cross(c - a).normalized();
    for (int k = 0; k < 100; ++k) {
      // A point of the triangle's plane near an edge or a corner, lifted
      // within the tolerance.
      Vec3 l(draw.u(), draw.u(), 0.0);
      l = 0.5 * (l + Vec3::Constant(1.0 / 3.0));
      l.z() = 1.0 - l.x() - l.y();
      const Vec3 on_plane = l.x() * a + l.y() * b + l.z() * c + 4.0 * slack * draw.u() * (b - a).normalized();
      const Vec3 q = on_plane + 0.9 * tolerance * draw.u() * n;
      const Vec3 qp = q - n * n.dot(q - a);
      const Vec3 closest = interpolate(barycentric(qp, a, b, c), a, b, c);
      const double out = (closest - qp).norm();
      if (std::abs(out - slack) < 1e-9 * scale) continue;  // on the border: rounding decides
      Vec3 bary;
      double dist2;
      const bool covered = project_to_patch_triangle(patch, patch.triangles[0], q, n, tolerance, bary, dist2);
      ASSERT_EQ(covered, out <= slack) << "trial " << trial << " point " << k << ": " << out / slack << " slacks out";
      const bool in = out < 1e-9 * scale;
      inside += in, in_slack += !in && out <= slack, beyond += out > slack;
    }
  }
  EXPECT_GT(inside, 10000);
  EXPECT_GT(in_slack, 1000);
  EXPECT_GT(beyond, 10000);
}

// TriangleProjection::OnPlane (the synthesis' projected fallback over one
// surface face, whose points and normals are affine in atlas coordinates)
// gives project()'s answers at those points: the same points covered, the
// same barycentric coordinates and distances up to rounding. Faces are
// drawn through random triangles at random tilts, their normals varying
// across them, so that all of project()'s tests (facing, tolerance, inside,
// slack) decide some of the points.
TEST(TriangleProjection, OnAFacePlaneAgreesWithThePerPointProjection) {
  RandomTriangle draw(11);
  Patch& patch = draw.patch;
  int covered = 0, rejected = 0, differ = 0, slack = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    const double scale = std::pow(10.0, 2.0 * draw.u());
    const Vec3 offset = 10.0 * scale * draw.vec();
    patch.positions = {offset + scale * draw.vec(), offset + scale * draw.vec(), offset + scale * draw.vec()};
    const double tolerance = scale * 0.1 * (1.5 + draw.u());
    const TriangleProjection projection(patch, patch.triangles[0], tolerance);
    const Vec3 tn =
        (patch.positions[1] - patch.positions[0]).cross(patch.positions[2] - patch.positions[0]).normalized();
    // The face: through the triangle's centroid, tilted, spanned by two
    // atlas axes of about a hundredth of the triangle per texel.
    const Vec3 centre = (patch.positions[0] + patch.positions[1] + patch.positions[2]) / 3.0;
    const Vec3 tilt = (tn + 0.3 * draw.vec()).normalized();
    const Vec3 u = tilt.cross(draw.vec()).normalized(), v = tilt.cross(u);
    TriangleProjection::Affine3 plane{centre + 0.05 * scale * draw.u() * tilt, 0.01 * scale * u, 0.01 * scale * v};
    TriangleProjection::Affine3 normal{tilt + 0.5 * draw.vec(), 0.005 * draw.vec(), 0.005 * draw.vec()};
    if (trial % 10 == 0) normal.origin = -normal.origin;  // a face facing away
    const TriangleProjection::OnPlane on_plane(projection, plane, normal);
    ASSERT_TRUE(on_plane.valid());
    for (int k = 0; k < 100; ++k) {
      const double x = 150.0 * draw.u(), y = 150.0 * draw.u();
      Vec3 bary, bary_plane;
      double dist2 = 0.0, dist2_plane = 0.0;
      const Vec3 n = normal.at(x, y).normalized();
      const bool full = projection.project(plane.at(x, y), n, bary, dist2);
      const bool fast = on_plane.project(x, y, bary_plane, dist2_plane);
      if (full != fast) {
        ++differ;  // only where a test's two sides meet, within rounding
        continue;
      }
      if (!full) {
        ++rejected;
        continue;
      }
      ++covered;
      slack += bary.minCoeff() == 0.0;
      ASSERT_LT((bary - bary_plane).lpNorm<Eigen::Infinity>(), 1e-9) << "trial " << trial << " point " << k;
      ASSERT_NEAR(dist2, dist2_plane, 1e-9 * scale * scale) << "trial " << trial << " point " << k;
    }
  }
  EXPECT_LE(differ, 3);
  EXPECT_GT(covered, 4000);
  EXPECT_GT(rejected, 20000);
  EXPECT_GT(slack, 100);
}

}  // namespace
}  // namespace fluidtex
