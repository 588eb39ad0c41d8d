// Patch coverage (tracking/patch_coverage.h): agreement with the exact
// locator, the nearest covering point, face samples.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "fluidtex/scenes/scenes.h"
#include "fluidtex/tracking/patch.h"
#include "fluidtex/tracking/patch_coverage.h"
#include "fluidtex/tracking/patch_locator.h"
#include "fluidtex/tracking/tracker.h"
#include "mesh_fixtures.h"
#include "test_util.h"

namespace fluidtex {
namespace {

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
  const double tol = t.settings().tracking.mpt();
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
  const FaceSamples fs = face_samples(surface, 0.3 * t.settings().tracking.d());
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

TEST(PatchCoverage, TheWholeSurfaceIsUncoveredWithoutPatches) {
  const FrameMesh grid = test::flat_grid(6);
  const SurfaceIndex surface(grid);
  const std::vector<Patch> none;
  EXPECT_DOUBLE_EQ(uncovered_area_fraction(surface, PatchCoverage(none, 0.01), 0.05), 1.0);
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

}  // namespace
}  // namespace fluidtex
