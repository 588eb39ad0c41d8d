// Which rule finds a deformed patch too distorted (update_distortion):
// rigid, stretched, mirrored and half-lost patches, the patch-scale test
// against the paper's per-vertex one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "fluidtex/tracking/patch_builder.h"
#include "fluidtex/tracking/patch_distortion.h"
#include "mesh_fixtures.h"

namespace fluidtex {
namespace {

/// A patch on a flat grid, then its positions mapped by `f`.
template <class F>
RetireCause judge(F&& f, DistortionTest test, bool drop_half = false) {
  const FrameMesh mesh = test::flat_grid(40);
  const SurfaceIndex surface(mesh);
  TrackingOptions o = TrackingOptions{}.resolved(1.0);
  o.radius = 0.15;
  o.distortion_test = test;
  SurfaceSample c;
  c.point = surface.closest_point(Vec3(0.5, 0.5, 0));
  c.normal = surface.normal_at(c.point);
  std::optional<Patch> p = build_patch(surface, c, o, 1, 1, 1, 0.0);
  if (!p) {
    ADD_FAILURE() << "no patch built";
    return RetireCause::None;
  }
  for (Vec3& x : p->positions) x = f(x);
  if (drop_half) {  // drop the vertices on one side of the centre (lost past mpt)
    std::vector<std::uint8_t> keep(p->positions.size(), 1);
    for (std::size_t v = 0; v < keep.size(); ++v) keep[v] = p->uvs[v].x() < -0.02 * o.d();
    remove_vertices(*p, keep, surface);
  }
  return update_distortion(*p, surface, o);
}

TEST(PatchDistortion, TheRuleThatFiredIsNamed) {
  const Vec3 c(0.5, 0.5, 0);
  auto rigid = [&](const Vec3& x) { return Vec3(c + Eigen::AngleAxisd(0.7, Vec3::UnitZ()) * (x - c)); };
  auto stretched = [&](const Vec3& x) { return Vec3(c + Vec3(3.5 * (x - c).x(), (x - c).y(), 0)); };
  auto mirrored = [&](const Vec3& x) { return Vec3(c + Vec3(-(x - c).x(), (x - c).y(), 0)); };
  // A mild stretch on a few triangles: the patch-scale test keeps the patch,
  // the per-vertex one does not.
  auto bump = [&](const Vec3& x) {  // a strip 0.03 wide stretched 3×, the rest moved rigidly
    return Vec3(x + Vec3(2.0 * std::clamp(x.x() - c.x() - 0.02, 0.0, 0.03), 0, 0));
  };
  for (DistortionTest test : {DistortionTest::Patch, DistortionTest::Vertex}) {
    SCOPED_TRACE(to_string(test));
    EXPECT_EQ(judge(rigid, test), RetireCause::None);
    EXPECT_EQ(judge(stretched, test), RetireCause::Quality);
    EXPECT_EQ(judge(mirrored, test), RetireCause::Flipped);
  }
  EXPECT_EQ(judge(rigid, DistortionTest::Patch, true), RetireCause::VerticesLost);
  EXPECT_EQ(judge(bump, DistortionTest::Patch), RetireCause::None);
  EXPECT_EQ(judge(bump, DistortionTest::Vertex), RetireCause::Quality);
}

// The patch-scale test weighs what the disk shows now: a band the flow has
// crushed into a sliver (a convergence line on a liquid surface, where
// surface material goes under) shows almost nothing, so it does not retire a
// patch whose other triangles are intact. Measured on blender-slosh before
// this rule: 546 of 561 patches retired as too distorted had their worst
// triangle compressed, not stretched (median smallest singular value 0.044).
TEST(PatchDistortion, ACrushedBandShowsLittleAUniformSqueezeRetires) {
  const double band = 0.08, squeeze = 20.0;  // the band |x − 0.5| < band, crushed 20×; the disk radius is 0.15
  auto crush_band = [&](const Vec3& x) {
    const double u = x.x() - 0.5;
    const double crushed = std::abs(u) < band ? u / squeeze : std::copysign(band / squeeze + std::abs(u) - band, u);
    return Vec3(0.5 + crushed, x.y(), x.z());
  };
  EXPECT_EQ(judge(crush_band, DistortionTest::Patch), RetireCause::None);
  auto squeeze_all = [](const Vec3& x) { return Vec3(0.5 + (x.x() - 0.5) / 3.5, x.y(), x.z()); };  // D = 3.5 > δmax
  EXPECT_EQ(judge(squeeze_all, DistortionTest::Patch), RetireCause::Quality);
  // The paper's per-vertex test retires both.
  EXPECT_EQ(judge(crush_band, DistortionTest::Vertex), RetireCause::Quality);
}

}  // namespace
}  // namespace fluidtex
