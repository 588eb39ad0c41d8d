// The preview renderer: a textured unit quad seen from the top shows its
// texture; OBJ read back from the writer.
#include <gtest/gtest.h>

#include <cmath>

#include "fluidtex/exemplar_gen.h"
#include "fluidtex/error.h"
#include "fluidtex/render.h"
#include "test_util.h"

namespace fluidtex {
namespace {

UVMesh unit_quad() {
  UVMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  m.normals.assign(4, Vec3(0, 0, 1));
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.uvs = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
  m.uv_triangles = m.triangles;
  return m;
}

TEST(Render, TopViewOfATexturedQuadReproducesTheTexture) {
  const Image texture = make_exemplar("gravel", 64, 2);
  RenderOptions o;
  o.width = 64;
  o.shade = false;
  o.min_u = o.min_v = 0.0;
  o.max_u = o.max_v = 1.0;
  const Image im = render_textured(unit_quad(), texture, o);
  ASSERT_EQ(im.width, 64);
  ASSERT_EQ(im.height, 64);
  double worst = 0.0;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(double(im.at(x, y, c)) - texture.at(x, y, c)));
    }
  }
  EXPECT_LT(worst, 1e-4);  // pixel centres land on texel centres
}

TEST(Render, ReadsTheObjTheWriterWrites) {
  test::TempDir dir;
  const UVMesh quad = unit_quad();
  write_uv_mesh_obj(dir.file("q.obj"), quad);
  const UVMesh back = read_uv_mesh_obj(dir.file("q.obj"));
  ASSERT_EQ(back.triangles.size(), 2u);
  ASSERT_EQ(back.positions.size(), 4u);
  for (std::size_t f = 0; f < 2; ++f) {
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = back.positions[back.triangles[f][k]];
      const Vec2& uv = back.uvs[back.uv_triangles[f][k]];
      EXPECT_NEAR(uv.x(), p.x(), 1e-6);  // the quad's uv equals its xy
      EXPECT_NEAR(uv.y(), p.y(), 1e-6);
    }
  }
  EXPECT_THROW(read_uv_mesh_obj(dir.file("missing.obj")), InputError);
}

}  // namespace
}  // namespace fluidtex
