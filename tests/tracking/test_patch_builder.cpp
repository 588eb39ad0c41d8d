// Patch creation (tracking/patch_builder.h, patch.h): the selection stays
// a disk, a flat patch is undistorted, border edges are marked; a recut
// keeps the texture where the old patch was intact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <set>

#include "fluidtex/geometry/distortion.h"
#include "fluidtex/tracking/advection.h"
#include "fluidtex/tracking/patch.h"
#include "fluidtex/tracking/patch_builder.h"
#include "fluidtex/tracking/patch_distortion.h"
#include "fluidtex/tracking/patch_locator.h"
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

TEST(PatchBuilder, APatchOnTrianglesFarLargerThanItsDiskStaysDiskSized) {
  // A sheet of 8 triangles, each half a unit across, and d = 0.01: the
  // triangle under the disk covers some 280 selection balls. Remeshed whole
  // at 0.35·d it would be some 20,000 triangles; cut to the selection cube,
  // the patch has the vertices of a patch on a fine mesh, within a few d.
  const FrameMesh mesh = test::flat_grid(2, 1.0);
  const SurfaceIndex surface(mesh);
  TrackingOptions o;
  o = o.resolved(1.0);
  o.radius = 0.01;
  std::string why;
  const Vec3 centre(0.3, 0.2, 0.0);
  const auto patch = build_patch(surface, sample_near(surface, centre), o, 1, 1, 1, 0.35 * o.d(), &why);
  ASSERT_TRUE(patch) << why;
  EXPECT_LT(patch->num_vertices(), 600u);
  EXPECT_GT(patch->num_vertices(), 50u);
  const double reach = kSelectionCube * (1.0 + o.selection_margin) * o.d();
  for (const Vec3& p : patch->positions) EXPECT_LE((p - centre).cwiseAbs().maxCoeff(), reach + 1e-9);
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

// --- Recut ---------------------------------------------------------------------

/// The texture coordinate (before anchor and scale) that `patch` shows at the
/// surface point `q` (normal `n`), through its nearest triangle there; false
/// where it does not cover q.
bool texture_at(const Patch& patch, const Vec3& q, const Vec3& n, double tolerance, Vec2& texture) {
  double best = std::numeric_limits<double>::infinity();
  for (const Tri& t : patch.triangles) {
    Vec3 bary;
    double dist2 = 0.0;
    if (!project_to_patch_triangle(patch, t, q, n, tolerance, bary, dist2) || !(dist2 < best)) continue;
    best = dist2;
    texture = patch.texture_offset + interpolate(patch.uvs, t, bary);
  }
  return std::isfinite(best);
}

/// A patch of disk radius `radius` built at `c0` on a flat unit grid, then
/// deformed by a map of the plane (as advection would leave it), and recut.
class FlatRecut {
 public:
  FlatRecut(double radius, const Vec3& c0) : mesh_(test::flat_grid(40)), surface_(mesh_), c0_(c0) {
    o_ = TrackingOptions{}.resolved(1.0);
    o_.radius = radius;
    SurfaceSample c;
    c.point = surface_.closest_point(c0);
    c.normal = surface_.normal_at(c.point);
    old_ = build_patch(surface_, c, o_, 7, 1, 1, 0.25 * o_.d());
  }
  bool built() const { return old_.has_value(); }
  Patch& old() { return *old_; }
  const TrackingOptions& options() const { return o_; }
  /// Moves the old patch's vertices and centre by `f`; returns update_distortion's verdict.
  template <class F>
  RetireCause deform(F&& f) {
    for (std::size_t v = 0; v < old_->num_vertices(); ++v) {
      old_->projections[v] = surface_.closest_point(f(old_->positions[v]));
      old_->positions[v] = old_->projections[v].position;
    }
    old_->centre.point = surface_.closest_point(f(c0_));
    return update_distortion(*old_, surface_, o_);
  }
  std::optional<Patch> recut() {
    std::optional<Patch> cut = recut_patch(*old_, surface_, o_, 1, 9, 0.25 * o_.d());
    if (cut) update_distortion(*cut, surface_, o_);
    return cut;
  }
  /// The old patch's texture coordinate at `q`.
  bool old_texture(const Vec3& q, Vec2& texture) const {
    return texture_at(*old_, q, Vec3::UnitZ(), o_.mpt(), texture);
  }

 private:
  FrameMesh mesh_;
  SurfaceIndex surface_;  // refers to mesh_
  Vec3 c0_;
  TrackingOptions o_;
  std::optional<Patch> old_;
};

TEST(Recut, ARigidlyMovedPatchKeepsItsTextureAndItsPlace) {
  const Vec3 c0(0.45, 0.5, 0);
  FlatRecut bench(0.15, c0);
  ASSERT_TRUE(bench.built());
  const double d = bench.options().d();
  Patch& old = bench.old();
  old.texture_offset = Vec2(0.3, -0.2);
  // Its texture shifted under it (uv 0 no longer at its centre): the fit
  // must shift the new texture too.
  for (Vec2& uv : old.uvs) uv += Vec2(0.02, -0.01);
  old.anchor = Vec2(0.25, 0.75);
  old.state = DiskState::FadingIn, old.kt = 0.4, old.created_frame = -5, old.close_frames = 2;
  // Turned 0.7 rad about its centre and carried along: its uv no longer
  // line up with a fresh flattening's.
  const Eigen::AngleAxisd turn(0.7, Vec3::UnitZ());
  const Vec3 shift(0.06, 0.02, 0.0);
  ASSERT_EQ(bench.deform([&](const Vec3& x) { return Vec3(turn * (x - c0) + c0 + shift); }), RetireCause::None);

  const std::optional<Patch> cut = bench.recut();
  ASSERT_TRUE(cut);
  EXPECT_EQ(cut->id, 7u);
  EXPECT_EQ(cut->state, DiskState::FadingIn);
  EXPECT_EQ(cut->kt, 0.4);
  EXPECT_EQ(cut->created_frame, -5);
  EXPECT_EQ(cut->recut_frame, 9);
  EXPECT_EQ(cut->close_frames, 2);
  EXPECT_EQ(cut->anchor, old.anchor);
  EXPECT_EQ(cut->centre.point.position, old.centre.point.position);
  int compared = 0;
  double worst = 0.0;
  for (std::size_t v = 0; v < cut->num_vertices(); ++v) {
    Vec2 before;
    // Inside the old patch's rim (just outside it, the projection's slack
    // clamps onto the rim).
    if (!bench.old_texture(cut->positions[v], before)) continue;
    if ((before - old.texture_offset).norm() > 1.5 * d) continue;
    ++compared;
    worst = std::max(worst, (cut->texture_offset + cut->uvs[v] - before).norm());
    // It shows there what the old patch showed: all of it.
    if ((before - old.texture_offset).norm() < d) EXPECT_NEAR(cut->recovery[v], 1.0, 1e-6);
  }
  EXPECT_GT(compared, 50);
  EXPECT_LT(worst, 1e-6 * d);
  // Its uv still have the disk centre at the origin (K_S's radial term).
  Vec2 centre;
  ASSERT_TRUE(texture_at(*cut, cut->centre.point.position, Vec3::UnitZ(), bench.options().mpt(), centre));
  EXPECT_LT((centre - cut->texture_offset).norm(), 1e-6);
}

TEST(Recut, WhereThePatchWasCrushedTheNewTextureFadesIn) {
  FlatRecut bench(0.15, Vec3(0.45, 0.5, 0));
  ASSERT_TRUE(bench.built());
  const double d = bench.options().d();
  // The band 0.5 < x < 0.58 crushed 20× (a convergence line), what lies
  // beyond it carried along.
  auto crush = [](double x) { return x < 0.5 ? x : x < 0.58 ? 0.5 + (x - 0.5) / 20 : x - 0.08 + 0.08 / 20; };
  bench.deform([&](const Vec3& x) { return Vec3(crush(x.x()), x.y(), 0.0); });
  const std::optional<Patch> cut = bench.recut();
  ASSERT_TRUE(cut);
  double intact_error = 0.0, band_recovery = 0.0, intact_recovery = 0.0;
  int intact = 0, band = 0;
  for (std::size_t v = 0; v < cut->num_vertices(); ++v) {
    const Vec3& x = cut->positions[v];
    Vec2 before;
    if (cut->uvs[v].norm() > d || !bench.old_texture(x, before)) continue;
    if (x.x() < 0.49) {  // left of the band: moved rigidly (not at all)
      ++intact;
      intact_error += (cut->texture_offset + cut->uvs[v] - before).norm();
      intact_recovery += cut->recovery[v];
    } else if (std::abs(x.x() - 0.502) < 0.015) {  // at the crushed band
      ++band;
      band_recovery += cut->recovery[v];
    }
  }
  ASSERT_GT(intact, 10);
  ASSERT_GT(band, 0);
  // Left of the band the texture stays exactly and shows fully; at the band,
  // where the old patch's Q_V fell (half its triangles crushed), the new
  // patch starts at what it showed.
  EXPECT_LT(intact_error / intact, 1e-6 * d);
  EXPECT_GT(intact_recovery / intact, 0.99);
  EXPECT_LT(band_recovery / band, 0.6);
}

TEST(Recut, AStretchedPatchIsCutUndistortedAroundTheSameTexture) {
  const Vec3 c0(0.5, 0.5, 0);
  FlatRecut bench(0.12, c0);
  ASSERT_TRUE(bench.built());
  const double d = bench.options().d();
  // Stretched 2.5× along x.
  ASSERT_NE(bench.deform([&](const Vec3& x) { return Vec3(c0.x() + 2.5 * (x.x() - c0.x()), x.y(), 0.0); }),
            RetireCause::None);
  const std::optional<Patch> cut = bench.recut();
  ASSERT_TRUE(cut);
  EXPECT_LT(cut->max_distortion, 1.01);
  // Along the line the stretch left alone (x = 0.5) the texture is where it
  // was; away from it, the stretch is gone.
  int on_line = 0;
  double line_error = 0.0, off_error = 0.0;
  for (std::size_t v = 0; v < cut->num_vertices(); ++v) {
    Vec2 before;
    if (cut->uvs[v].norm() > d || !bench.old_texture(cut->positions[v], before)) continue;
    const double error = (cut->texture_offset + cut->uvs[v] - before).norm();
    if (std::abs(cut->positions[v].x() - c0.x()) < 1e-3 * d) {
      ++on_line, line_error = std::max(line_error, error);
    } else {
      off_error = std::max(off_error, error);
    }
  }
  ASSERT_GT(on_line, 2);
  EXPECT_LT(line_error, 1e-6 * d);
  EXPECT_GT(off_error, 0.1 * d);
}

}  // namespace
}  // namespace fluidtex
