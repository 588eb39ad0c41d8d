// The preview renderer: a textured unit quad seen from the top shows its
// texture; cameras project known points where expected; the G-buffer gives
// the right face and barycentrics; overlays draw only where they should; the
// contact sheet's size; OBJ read back from the writer.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "fluidtex/inspect/overlays.h"
#include "fluidtex/inspect/render.h"
#include "fluidtex/io/uv_mesh_io.h"
#include "fluidtex/scenes/exemplar_gen.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/random.h"
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

RenderOptions unit_top(int width) {
  RenderOptions o;
  o.width = width;
  o.shade = false;
  o.min_u = o.min_v = 0.0;
  o.max_u = o.max_v = 1.0;
  return o;
}

Image flat_grey(float v) {
  Image im;
  im.width = im.height = 4, im.channels = 3;
  im.pixels.assign(4 * 4 * 3, v);
  return im;
}

TEST(Render, RenderReturnsTheSameImageAsRenderTextured) {
  const Image texture = make_exemplar("gravel", 32, 3);
  RenderOptions o;
  o.width = 48;
  o.view = View::Front;
  UVMesh quad = unit_quad();
  quad.positions[2].z() = 0.4;  // not flat: shading and depth matter
  const RenderResult r = render(quad, texture, o);
  EXPECT_EQ(r.color.pixels, render_textured(quad, texture, o).pixels);
  EXPECT_EQ(r.gbuffer.width, r.color.width);
  EXPECT_EQ(r.gbuffer.height, r.color.height);
  EXPECT_EQ(r.camera.width, r.color.width);
}

TEST(Render, PerspectiveCameraProjectsKnownPoints) {
  // Looking down −z (nearly parallel to +z): up is +y, right is +x.
  const Camera top = Camera::perspective_at(Vec3(0, 0, 5), Vec3(0, 0, 0), 40.0, 64, 48);
  const Vec3 c = top.project(Vec3(0, 0, 0));
  EXPECT_NEAR(c.x(), 32.0, 1e-12);
  EXPECT_NEAR(c.y(), 24.0, 1e-12);
  EXPECT_NEAR(c.z(), 5.0, 1e-12);
  const double focal = 24.0 / std::tan(20.0 * std::numbers::pi / 180.0);
  EXPECT_NEAR(top.focal, focal, 1e-12);
  const Vec3 px = top.project(Vec3(1, 0, 0)), py = top.project(Vec3(0, 1, 0));
  EXPECT_NEAR(px.x(), 32.0 + focal / 5.0, 1e-9);
  EXPECT_NEAR(px.y(), 24.0, 1e-9);
  EXPECT_NEAR(py.y(), 24.0 - focal / 5.0, 1e-9);  // +y is up on screen
  // A half-fov point lands on the top edge.
  EXPECT_NEAR(top.project(Vec3(0, 5 * std::tan(20.0 * std::numbers::pi / 180.0), 0)).y(), 0.0, 1e-9);
  // From the side (looking along +x... from −x): up is +z.
  const Camera side = Camera::perspective_at(Vec3(-4, 0, 0), Vec3(0, 0, 0), 60.0, 100, 80);
  EXPECT_NEAR(side.project(Vec3(0, 0, 0)).x(), 50.0, 1e-12);
  EXPECT_LT(side.project(Vec3(0, 0, 1)).y(), 40.0);
  EXPECT_NEAR(side.project(Vec3(0, 0, 1)).x(), 50.0, 1e-9);
  EXPECT_GT(side.project(Vec3(0, -1, 0)).x(), 50.0);  // right-handed: −y is to the right
  EXPECT_FALSE(side.in_front(Vec3(-5, 0, 0)));
  EXPECT_THROW(Camera::perspective_at(Vec3(1, 1, 1), Vec3(1, 1, 1), 40.0, 10, 10), InputError);
  EXPECT_THROW(Camera::perspective_at(Vec3(0, 0, 1), Vec3(0, 0, 0), 180.0, 10, 10), InputError);
  // Image displacement: project(p + d) − project(p).
  const Vec2 d = top.image_displacement(Vec3(0, 0, 0), Vec3(0.5, 0.25, 0));
  EXPECT_NEAR(d.x(), 0.5 * focal / 5.0, 1e-9);
  EXPECT_NEAR(d.y(), -0.25 * focal / 5.0, 1e-9);
  const Camera ortho = make_camera({}, unit_top(64));
  const Vec2 od = ortho.image_displacement(Vec3(0.3, 0.3, 0.7), Vec3(0.25, 0.5, 3.0));
  EXPECT_NEAR(od.x(), 16.0, 1e-9);
  EXPECT_NEAR(od.y(), -32.0, 1e-9);
  EXPECT_NEAR(ortho.project(Vec3(0.5, 0.25, 0.1)).x(), 32.0, 1e-12);
  EXPECT_NEAR(ortho.project(Vec3(0.5, 0.25, 0.1)).y(), 48.0, 1e-12);
}

TEST(Render, OrthographicGBufferGivesFaceAndBarycentrics) {
  const RenderResult r = render(unit_quad(), flat_grey(0.5f), unit_top(64));
  const GBuffer& g = r.gbuffer;
  ASSERT_EQ(g.width, 64);
  ASSERT_EQ(g.height, 64);
  // Pixel (10, 60): u = 10.5/64, v = 1 − 60.5/64, below the diagonal: face 0
  // (0,0)-(1,0)-(1,1), where u = b1 + b2 and v = b2.
  {
    const double u = 10.5 / 64, v = 1 - 60.5 / 64;
    ASSERT_EQ(g.face_at(10, 60), 0);
    EXPECT_NEAR(g.bary_at(10, 60)[0], 1 - u, 1e-12);
    EXPECT_NEAR(g.bary_at(10, 60)[1], u - v, 1e-12);
    EXPECT_NEAR(g.bary_at(10, 60)[2], v, 1e-12);
    EXPECT_NEAR(g.depth[g.index(10, 60)], 0.0, 1e-12);
  }
  // Pixel (5, 5): above the diagonal: face 1 (0,0)-(1,1)-(0,1), u = b1, v = b1 + b2.
  {
    const double u = 5.5 / 64, v = 1 - 5.5 / 64;
    ASSERT_EQ(g.face_at(5, 5), 1);
    EXPECT_NEAR(g.bary_at(5, 5)[1], u, 1e-12);
    EXPECT_NEAR(g.bary_at(5, 5)[2], v - u, 1e-12);
  }
  // With the default framing (3% margin) the corners are background.
  RenderOptions framed;
  framed.width = 64;
  const GBuffer h = render(unit_quad(), flat_grey(0.5f), framed).gbuffer;
  EXPECT_EQ(h.face_at(0, 0), -1);
  EXPECT_TRUE(std::isinf(h.depth[0]));
  EXPECT_EQ(h.face_at(32, 40), 0);
  EXPECT_EQ(h.face_at(20, 10), 1);
}

TEST(Render, PerspectiveGBufferIsPerspectiveCorrect) {
  // An oblique view of the quad: every covered pixel's barycentric point
  // projects back onto that pixel's centre, at the stored depth.
  RenderOptions o;
  o.width = 80;
  o.height = 60;
  o.perspective = true;
  o.eye = Vec3(0.3, -1.6, 1.2);
  o.target = Vec3(0.5, 0.5, 0.0);
  const UVMesh quad = unit_quad();
  const RenderResult r = render(quad, flat_grey(0.5f), o);
  const GBuffer& g = r.gbuffer;
  ASSERT_EQ(g.width, 80);
  ASSERT_EQ(g.height, 60);
  ASSERT_GE(g.face_at(40, 30), 0);  // the target is on the quad
  int covered = 0;
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      const int f = g.face_at(x, y);
      if (f < 0) continue;
      ++covered;
      const Tri& t = quad.triangles[f];
      const Vec3& b = g.bary_at(x, y);
      EXPECT_NEAR(b.sum(), 1.0, 1e-12);
      const Vec3 p = b[0] * quad.positions[t[0]] + b[1] * quad.positions[t[1]] + b[2] * quad.positions[t[2]];
      const Vec3 q = r.camera.project(p);
      EXPECT_NEAR(q.x(), x + 0.5, 1e-9);
      EXPECT_NEAR(q.y(), y + 0.5, 1e-9);
      EXPECT_NEAR(q.z(), g.depth[g.index(x, y)], 1e-9);
    }
  }
  EXPECT_GT(covered, 400);
  // The target pixel is the target point: (0.5, 0.5) on the diagonal.
  const Tri& t = quad.triangles[g.face_at(40, 30)];
  const Vec3& b = g.bary_at(40, 30);
  const Vec3 p = b[0] * quad.positions[t[0]] + b[1] * quad.positions[t[1]] + b[2] * quad.positions[t[2]];
  EXPECT_LT((p - o.target).norm(), 0.1);
}

/// A patch: the square [lo, hi]² at height z, two triangles.
Patch square_patch(std::uint32_t id, double lo, double hi, double z, DiskState state) {
  Patch p;
  p.id = id;
  p.state = state;
  p.positions = {Vec3(lo, lo, z), Vec3(hi, lo, z), Vec3(hi, hi, z), Vec3(lo, hi, z)};
  p.triangles = {{0, 1, 2}, {0, 2, 3}};
  p.centre.point.position = Vec3(0.5 * (lo + hi), 0.5 * (lo + hi), z);
  return p;
}

/// Pixels whose colour differs between two images.
std::vector<std::pair<int, int>> changed(const Image& a, const Image& b) {
  std::vector<std::pair<int, int>> out;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        if (a.at(x, y, c) != b.at(x, y, c)) {
          out.emplace_back(x, y);
          break;
        }
      }
    }
  }
  return out;
}

TEST(Render, BorderOverlayDrawsOnlyThePatchOutline) {
  const RenderResult base = render(unit_quad(), flat_grey(0.5f), unit_top(64));
  RenderResult r = base;
  Canvas canvas{r.color, r.gbuffer, r.camera, 0.005};
  const Patch patch = square_patch(7, 0.25, 0.75, 0.0, DiskState::Active);
  draw_patch_borders(canvas, {patch});
  const auto px = changed(base.color, r.color);
  ASSERT_GT(px.size(), 100u);  // four sides of 32 pixels
  const LinearRgb expected = rgb_from_srgb8(id_color(7));
  for (const auto& [x, y] : px) {
    // On the square's outline (pixels 16 and 48 in either axis), never on the diagonal inside.
    const bool on_x = (x == 16 || x == 47 || x == 48) && y >= 15 && y <= 48;
    const bool on_y = (y == 16 || y == 15 || y == 48) && x >= 16 && x <= 48;
    EXPECT_TRUE(on_x || on_y) << x << "," << y;
    for (int c = 0; c < 3; ++c) EXPECT_EQ(r.color.at(x, y, c), expected[c]);
  }
  // A patch below the surface (seen from the top) is hidden.
  RenderResult hidden = base;
  Canvas under{hidden.color, hidden.gbuffer, hidden.camera, 0.005};
  draw_patch_borders(under, {square_patch(7, 0.25, 0.75, -0.5, DiskState::Active)});
  EXPECT_TRUE(changed(base.color, hidden.color).empty());
}

TEST(Render, StateAndVelocityOverlaysDrawAroundTheirPoints) {
  const RenderResult base = render(unit_quad(), flat_grey(0.5f), unit_top(64));
  RenderResult r = base;
  Canvas canvas{r.color, r.gbuffer, r.camera, 0.005};
  draw_disk_states(canvas, {square_patch(1, 0.25, 0.75, 0.0, DiskState::FadingOutClose)}, 4.0);
  const auto px = changed(base.color, r.color);
  ASSERT_FALSE(px.empty());
  for (const auto& [x, y] : px) EXPECT_LE(std::hypot(x + 0.5 - 32, y + 0.5 - 32), 4.0) << x << "," << y;
  const LinearRgb yellow = rgb_from_srgb8(state_color(DiskState::FadingOutClose));
  EXPECT_EQ(r.color.at(32, 32, 0), yellow[0]);
  // The four states have distinct colours.
  for (int a = 0; a < 4; ++a) {
    for (int b = a + 1; b < 4; ++b) EXPECT_NE(state_color(DiskState(a)), state_color(DiskState(b)));
  }
  // Velocity arrows: one vertex moving +x draws to the right of it only.
  FrameMesh mesh;
  mesh.positions = {Vec3(0.25, 0.5, 0.0)};
  mesh.velocities = {Vec3(2.0, 0.0, 0.0)};
  RenderResult v = base;
  Canvas arrows{v.color, v.gbuffer, v.camera, 0.005};
  draw_velocities(arrows, mesh, 0.125, 16);  // 0.25 units = 16 pixels
  const auto apx = changed(base.color, v.color);
  ASSERT_GE(apx.size(), 16u);
  for (const auto& [x, y] : apx) {
    EXPECT_GE(x, 16);
    EXPECT_LE(x, 32);
    EXPECT_LE(std::abs(y - 32), 4);
  }
}

TEST(Render, ContactSheetIsANearSquareGrid) {
  auto frames = [](int n, int w, int h) {
    std::vector<Image> v(n);
    for (Image& im : v) {
      im.width = w, im.height = h, im.channels = 3;
      im.pixels.assign(static_cast<std::size_t>(w) * h * 3, 0.5f);
    }
    return v;
  };
  const Image five = contact_sheet(frames(5, 10, 8), {"1", "2", "3", "4", "5"}, 4);
  EXPECT_EQ(five.width, 3 * 10 + 4 * 4);  // 3 columns, 2 rows
  EXPECT_EQ(five.height, 2 * 8 + 3 * 4);
  const Image four = contact_sheet(frames(4, 10, 8), {}, 2);
  EXPECT_EQ(four.width, 2 * 10 + 3 * 2);
  EXPECT_EQ(four.height, 2 * 8 + 3 * 2);
  const Image one = contact_sheet(frames(1, 10, 8), {}, 0);
  EXPECT_EQ(one.width, 10);
  EXPECT_EQ(one.height, 8);
  EXPECT_EQ(contact_sheet(frames(10, 7, 9), {}, 1).width, 4 * 7 + 5);
  EXPECT_TRUE(contact_sheet({}, {}).empty());
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
