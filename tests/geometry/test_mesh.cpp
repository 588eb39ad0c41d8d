// Flat-triangle helpers (geometry/mesh.h): slab extents and the outline of
// a chart laid in the plane, which the atlas packer's profiles are made of.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "fluidtex/geometry/mesh.h"
#include "mesh_fixtures.h"

namespace fluidtex {
namespace {

/// Per face, its corners' (x, y).
std::vector<std::array<Vec2, 3>> flat_corners(const FrameMesh& mesh) {
  std::vector<std::array<Vec2, 3>> corners(mesh.triangles.size());
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    for (int k = 0; k < 3; ++k) corners[f][k] = mesh.positions[mesh.triangles[f][k]].head<2>();
  }
  return corners;
}

/// Over slabs across the whole layout along both axes, the number whose
/// extent over the outline's border edges (and its loose faces, if
/// `with_loose`) differs from the extent over all faces in the slab.
int slabs_missed(const FrameMesh& mesh, bool with_loose = true) {
  const auto corners = flat_corners(mesh);
  const FlatOutline outline = flat_outline(mesh.triangles, corners);
  const double inf = std::numeric_limits<double>::infinity();
  int met = 0, missed = 0;
  for (int axis = 0; axis < 2; ++axis) {
    for (int i = -10; i < 80; ++i) {
      const double s0 = 0.0173 * i - 0.2, s1 = s0 + (i % 3 == 0 ? 0.0 : 0.031 * (i % 5 + 1));
      double all_lo = inf, all_hi = -inf;
      for (const auto& t : corners) {
        double lo, hi;
        if (slab_extent(t, axis, s0, s1, lo, hi)) all_lo = std::min(all_lo, lo), all_hi = std::max(all_hi, hi);
      }
      double lo = inf, hi = -inf;
      for (const int e : outline.border_edges) {
        segment_slab_extent(corners[e / 3][e % 3], corners[e / 3][(e % 3 + 1) % 3], axis, s0, s1, lo, hi);
      }
      for (const int f : with_loose ? outline.loose_faces : std::vector<int>{}) {
        double a, b;
        if (slab_extent(corners[f], axis, s0, s1, a, b)) lo = std::min(lo, a), hi = std::max(hi, b);
      }
      met += all_lo <= all_hi;
      missed += lo != all_lo || hi != all_hi;
    }
  }
  EXPECT_GT(met, 100);  // the slabs do cross the layout
  return missed;
}

TEST(FlatOutline, AGridIsBoundedByItsPerimeter) {
  const FrameMesh grid = test::flat_grid(8, 1.0);
  const FlatOutline outline = flat_outline(grid.triangles, flat_corners(grid));
  EXPECT_EQ(outline.border_edges.size(), 4u * 8u);
  EXPECT_TRUE(outline.loose_faces.empty());
  EXPECT_EQ(slabs_missed(grid), 0);
}

TEST(FlatOutline, FoldedAndFlatFacesAreKeptWhole) {
  // An inner vertex pushed past its neighbour folds faces over the others;
  // one pushed out beyond the grid's side folds faces out past the
  // perimeter, which the border edges alone would miss; a vertex moved onto
  // the line of two others lays a face flat (the grid's corners are exact
  // in binary: its area is exactly 0).
  FrameMesh folded = test::flat_grid(8, 1.0);
  folded.positions[2 * 9 + 2] = Vec3(0.4, 0.27, 0.0);
  EXPECT_EQ(slabs_missed(folded), 0);
  EXPECT_FALSE(flat_outline(folded.triangles, flat_corners(folded)).loose_faces.empty());

  FrameMesh poking = test::flat_grid(8, 1.0);
  poking.positions[4 * 9 + 1] = Vec3(-0.3, 0.55, 0.0);
  EXPECT_EQ(slabs_missed(poking), 0);
  EXPECT_GT(slabs_missed(poking, false), 0);  // the folded faces stick out

  FrameMesh flat = test::flat_grid(8, 1.0);
  const Tri& t = flat.triangles[20];
  flat.positions[t[2]] = 0.5 * (flat.positions[t[0]] + flat.positions[t[1]]);
  const FlatOutline outline = flat_outline(flat.triangles, flat_corners(flat));
  EXPECT_NE(std::find(outline.loose_faces.begin(), outline.loose_faces.end(), 20), outline.loose_faces.end());
  EXPECT_EQ(slabs_missed(flat), 0);
}

TEST(FlatOutline, ATriangleInASlabIsItsEdgesInTheSlab) {
  const std::array<Vec2, 3> t = {Vec2(0.1, 0.2), Vec2(0.9, 0.35), Vec2(0.4, 0.95)};
  for (int axis = 0; axis < 2; ++axis) {
    for (double s0 = -0.1; s0 < 1.0; s0 += 0.07) {
      double lo, hi;
      const bool met = slab_extent(t, axis, s0, s0 + 0.05, lo, hi);
      double elo = std::numeric_limits<double>::infinity(), ehi = -elo;
      for (int k = 0; k < 3; ++k) segment_slab_extent(t[k], t[(k + 1) % 3], axis, s0, s0 + 0.05, elo, ehi);
      EXPECT_EQ(met, elo <= ehi);
      if (met) {
        EXPECT_EQ(lo, elo);
        EXPECT_EQ(hi, ehi);
      }
    }
  }
}

}  // namespace
}  // namespace fluidtex
