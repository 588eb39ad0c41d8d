// flatten_lscm and remesh_disk (geometry/parameterization.h) on meshes whose
// answer is known: a flat grid flattens isometrically, a spherical cap keeps
// its area, remeshing keeps the area and the border; clip_disk_to_cube
// (geometry/disk_clip.h) cuts a coarse sheet to the cube's square.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "fluidtex/geometry/disk_clip.h"
#include "fluidtex/geometry/parameterization.h"
#include "mesh_fixtures.h"

namespace fluidtex {
namespace {

DiskMesh disk_of(const FrameMesh& mesh) {
  std::vector<int> all(mesh.triangles.size());
  for (std::size_t f = 0; f < all.size(); ++f) all[f] = static_cast<int>(f);
  return extract_faces(mesh, all);
}

double area_3d(const DiskMesh& m) {
  double a = 0.0;
  for (const Tri& t : m.triangles) a += triangle_area(m.positions, t);
  return a;
}

double signed_area_uv(const std::vector<Vec2>& uv, const Tri& t) { return signed_area(uv[t[0]], uv[t[1]], uv[t[2]]); }

TEST(Parameterization, FlatGridFlattensIsometricallyAndKeepsOrientation) {
  const DiskMesh grid = disk_of(test::flat_grid(6, 2.0));
  std::vector<Vec2> uv;
  std::string failure;
  ASSERT_TRUE(flatten_lscm(grid, uv, &failure)) << failure;
  ASSERT_EQ(uv.size(), grid.positions.size());
  // A plane maps by a similarity, rescaled to metric: every distance kept.
  double worst = 0.0;
  for (std::size_t i = 0; i < uv.size(); ++i) {
    for (std::size_t j = i + 1; j < uv.size(); ++j) {
      worst = std::max(worst, std::abs((uv[i] - uv[j]).norm() - (grid.positions[i] - grid.positions[j]).norm()));
    }
  }
  EXPECT_LT(worst, 1e-6);
  for (const Tri& t : grid.triangles) EXPECT_GT(signed_area_uv(uv, t), 0.0);  // z-up grid: counter-clockwise
}

TEST(Parameterization, CurvedCapKeepsItsAreaAndClosedMeshesAreRefused) {
  const FrameMesh sphere = test::uv_sphere(12, 24, 1.0);
  // The northern cap (faces above z = 0.5) is a disk.
  std::vector<int> cap;
  for (std::size_t f = 0; f < sphere.triangles.size(); ++f) {
    const Tri& t = sphere.triangles[f];
    if ((sphere.positions[t[0]] + sphere.positions[t[1]] + sphere.positions[t[2]]).z() / 3.0 > 0.5)
      cap.push_back(static_cast<int>(f));
  }
  const DiskMesh disk = extract_faces(sphere, cap);
  std::vector<Vec2> uv;
  ASSERT_TRUE(flatten_lscm(disk, uv));
  double area_uv = 0.0;
  for (const Tri& t : disk.triangles) {
    EXPECT_GT(signed_area_uv(uv, t), 0.0);
    area_uv += signed_area_uv(uv, t);
  }
  EXPECT_NEAR(area_uv / area_3d(disk), 1.0, 1e-9);
  // A closed sphere is no disk.
  std::string failure;
  EXPECT_FALSE(flatten_lscm(disk_of(sphere), uv, &failure));
  EXPECT_FALSE(failure.empty());
}

TEST(Parameterization, RemeshKeepsAreaAndBorderAndMeetsTheEdgeLength) {
  DiskMesh grid = disk_of(test::flat_grid(4, 1.0));
  const std::size_t before = grid.triangles.size();
  const double edge = 0.05;
  ASSERT_TRUE(remesh_disk(grid, edge));
  EXPECT_GT(grid.triangles.size(), 10 * before);
  EXPECT_NEAR(area_3d(grid), 1.0, 1e-9);
  // Vertices stay on the square; the border keeps its exact shape.
  std::map<std::pair<int, int>, int> edge_use;
  double longest = 0.0;
  for (const Tri& t : grid.triangles) {
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      ++edge_use[{std::min(a, b), std::max(a, b)}];
      longest = std::max(longest, (grid.positions[a] - grid.positions[b]).norm());
    }
  }
  for (const Vec3& p : grid.positions) {
    EXPECT_NEAR(p.z(), 0.0, 1e-12);
    EXPECT_GE(p.x(), -1e-12);
    EXPECT_LE(p.x(), 1.0 + 1e-12);
    EXPECT_GE(p.y(), -1e-12);
    EXPECT_LE(p.y(), 1.0 + 1e-12);
  }
  for (const auto& [e, uses] : edge_use) {
    if (uses != 1) continue;  // border edge: on a side of the square
    const Vec3 &a = grid.positions[e.first], &b = grid.positions[e.second];
    const bool on_side =
        (std::abs(a.x() - b.x()) < 1e-12 && (std::abs(a.x()) < 1e-12 || std::abs(a.x() - 1) < 1e-12)) ||
        (std::abs(a.y() - b.y()) < 1e-12 && (std::abs(a.y()) < 1e-12 || std::abs(a.y() - 1) < 1e-12));
    EXPECT_TRUE(on_side);
  }
  // Edges above 4/3 of the target are split; the tangential relaxation that
  // follows moves vertices a little (measured: longest 1.34 × the target).
  EXPECT_LE(longest, 1.5 * edge);
}

TEST(Parameterization, RemeshRefusesANonManifoldMeshAndLeavesIt) {
  // Three triangles on one edge.
  DiskMesh fan;
  fan.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0), Vec3(0.5, -1, 0), Vec3(0.5, 0, 1)};
  fan.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  const DiskMesh before = fan;
  EXPECT_FALSE(remesh_disk(fan, 0.1));
  EXPECT_EQ(fan.triangles, before.triangles);
  EXPECT_EQ(fan.positions.size(), before.positions.size());
}

TEST(DiskClip, ACoarseSheetIsCutToTheCubesSquareAndStaysADisk) {
  // Two triangles 2 units across; the cube of half-size 0.1 around a point
  // of the sheet holds a 0.2 × 0.2 square of it, which is what is left: a
  // disk that flattens.
  DiskMesh sheet = disk_of(test::flat_grid(1, 2.0));
  const Vec3 centre(0.7, 0.4, 0.0);
  ASSERT_TRUE(clip_disk_to_cube(sheet, centre, 0.1));
  EXPECT_NEAR(area_3d(sheet), 0.04, 1e-12);
  for (const Vec3& p : sheet.positions) EXPECT_LE((p - centre).cwiseAbs().maxCoeff(), 0.1 + 1e-12);
  std::vector<Vec2> uv;
  EXPECT_TRUE(flatten_lscm(sheet, uv));
  // A mesh inside the cube is left as it is.
  DiskMesh small = disk_of(test::flat_grid(4, 0.1, 0.0, 0.65, 0.35));
  const DiskMesh before = small;
  EXPECT_FALSE(clip_disk_to_cube(small, centre, 0.1));
  EXPECT_EQ(small.positions, before.positions);
  EXPECT_EQ(small.triangles, before.triangles);
}

}  // namespace
}  // namespace fluidtex
