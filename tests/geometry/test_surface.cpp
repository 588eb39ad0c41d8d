// SurfaceIndex (geometry/surface.h): normals at surface points.
#include <gtest/gtest.h>

#include "fluidtex/geometry/surface.h"
#include "mesh_fixtures.h"

namespace fluidtex {
namespace {

TEST(Surface, AFoldedFaceTakesItsOwnNormal) {
  // A flat grid (normal +z) with one interior vertex pushed past its
  // neighbour: the faces it drags across fold over (normal −z), while the
  // area-weighted vertex normals around them still point up.
  FrameMesh grid = test::flat_grid(4, 1.0);
  grid.positions[2 * 5 + 2] = Vec3(0.85, 0.55, 0.0);
  const SurfaceIndex surface(grid);
  int folded = 0;
  for (std::size_t f = 0; f < grid.triangles.size(); ++f) {
    const SurfacePoint centre = surface.at(static_cast<int>(f), Vec3::Constant(1.0 / 3.0));
    const Vec3 n = surface.normal_at(centre);
    const Vec3& face = surface.face_normals()[f];
    EXPECT_NEAR(n.norm(), 1.0, 1e-12);
    EXPECT_GT(n.dot(face), 0.0) << "face " << f;  // never a normal behind its own face
    if (face.z() < 0.0) {
      ++folded;
      EXPECT_NEAR((n - face).norm(), 0.0, 1e-12) << "face " << f;
      // Its vertices' normals point up: their blend alone is behind the face.
      Vec3 blend = Vec3::Zero();
      for (int k = 0; k < 3; ++k) blend += surface.vertex_normals()[grid.triangles[f][k]];
      EXPECT_LT(blend.dot(face), 0.0) << "face " << f;
    } else {
      EXPECT_GT(n.z(), 0.9) << "face " << f;  // the blend, as before, on the flat faces
    }
  }
  ASSERT_GE(folded, 1);
}

}  // namespace
}  // namespace fluidtex
