// Patch creation (tracking/patch_builder.h, patch.h): the selection stays
// a disk, a flat patch is undistorted, border edges are marked.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "fluidtex/geometry/distortion.h"
#include "fluidtex/tracking/advection.h"
#include "fluidtex/tracking/patch.h"
#include "fluidtex/tracking/patch_builder.h"
#include "fluidtex/tracking/patch_distortion.h"
#include "mesh_fixtures.h"
#include "test_util.h"

namespace fluidtex {
namespace {

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

}  // namespace
}  // namespace fluidtex
