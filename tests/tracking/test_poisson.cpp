// Poisson disks (tracking/poisson.h): Eq. 1 and the plane test, and the
// sampling's properties: maximal, within the criterion, the birth margin,
// small components, the kill distance.
#include <gtest/gtest.h>

#include <algorithm>

#include "fluidtex/tracking/poisson.h"
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

}  // namespace
}  // namespace fluidtex
