// grow_disk_region (geometry/disk_region.h): every region it grows is a
// topological disk, follows the priority, honours accept and the size limit.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "fluidtex/geometry/disk_region.h"
#include "mesh_fixtures.h"

namespace fluidtex {
namespace {

/// V − E + F of the faces `region` of `mesh`, and the number of boundary edges.
std::pair<int, int> euler_and_border(const FrameMesh& mesh, const std::vector<int>& region) {
  std::set<int> vertices;
  std::map<std::pair<int, int>, int> edges;
  for (int f : region) {
    const Tri& t = mesh.triangles[f];
    for (int k = 0; k < 3; ++k) {
      vertices.insert(t[k]);
      ++edges[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
    }
  }
  int border = 0;
  for (const auto& [e, n] : edges) border += n == 1;
  return {static_cast<int>(vertices.size()) - static_cast<int>(edges.size()) + static_cast<int>(region.size()), border};
}

Vec3 centroid(const FrameMesh& mesh, int f) {
  const Tri& t = mesh.triangles[f];
  return (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
}

TEST(DiskRegion, GrowsDisksInPriorityOrderUpToTheLimit) {
  const FrameMesh sphere = test::uv_sphere(16, 32, 1.0);
  const SurfaceIndex surface(sphere);
  const int seed = 100;
  DiskRegionOptions o;
  o.accept = [](int) { return true; };
  o.priority = [&](int f) { return (centroid(sphere, f) - centroid(sphere, seed)).norm(); };
  for (std::size_t limit : {1u, 7u, 60u, 300u}) {
    o.max_faces = limit;
    const std::vector<int> region = grow_disk_region(surface, seed, o);
    ASSERT_EQ(region.size(), limit);
    EXPECT_EQ(region.front(), seed);
    EXPECT_EQ(std::set<int>(region.begin(), region.end()).size(), region.size());
    EXPECT_EQ(euler_and_border(sphere, region).first, 1) << limit;  // a disk
  }
  // Unlimited on a closed sphere: it never closes over (still a disk, with a border).
  o.max_faces = 0;
  const std::vector<int> all = grow_disk_region(surface, seed, o);
  EXPECT_LT(all.size(), sphere.triangles.size());
  EXPECT_GT(all.size(), sphere.triangles.size() * 9 / 10);
  const auto [chi, border] = euler_and_border(sphere, all);
  EXPECT_EQ(chi, 1);
  EXPECT_GT(border, 0);
}

TEST(DiskRegion, NeverTakesARejectedFaceNorClosesAroundAHole) {
  const FrameMesh grid = test::flat_grid(12);
  const SurfaceIndex surface(grid);
  // Reject a block in the middle: the region grows around it, as a disk.
  auto rejected = [&](int f) {
    const Vec3 c = centroid(grid, f);
    return std::abs(c.x() - 0.5) < 0.15 && std::abs(c.y() - 0.5) < 0.15;
  };
  DiskRegionOptions o;
  o.accept = [&](int f) { return !rejected(f); };
  o.priority = [&](int f) { return centroid(grid, f).x(); };
  const std::vector<int> region = grow_disk_region(surface, 0, o);
  for (int f : region) EXPECT_FALSE(rejected(f)) << f;
  EXPECT_EQ(euler_and_border(grid, region).first, 1);
  int accepted = 0;
  for (std::size_t f = 0; f < grid.triangles.size(); ++f) accepted += !rejected(static_cast<int>(f));
  EXPECT_LT(static_cast<int>(region.size()), accepted);  // the ring around the hole stays open
  EXPECT_GT(static_cast<int>(region.size()), accepted * 8 / 10);
}

}  // namespace
}  // namespace fluidtex
