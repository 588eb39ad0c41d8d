// Patch location (tracking/patch_locator.h): the prism pre-test and the
// projection onto one patch triangle, per point and over a face's plane.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fluidtex/tracking/patch.h"
#include "fluidtex/tracking/patch_locator.h"
#include "mesh_fixtures.h"
#include "test_util.h"

namespace fluidtex {
namespace {

// Random draws for the tests of one patch triangle against points around it.
struct RandomTriangle {
  explicit RandomTriangle(unsigned seed) : rng(seed) { patch.triangles = {Tri{0, 1, 2}}; }
  double u() { return unit(rng); }  ///< uniform in [−1, 1)
  Vec3 vec() { return Vec3(u(), u(), u()); }
  std::mt19937 rng;
  std::uniform_real_distribution<double> unit{-1.0, 1.0};
  Patch patch;
};

// TrianglePrism::may_cover is a pre-test: it may pass points the full
// projection rejects, never the reverse. Points are drawn around random
// triangles, many of them within a few slacks of an edge, a corner or the
// tolerance, where the two tests are closest.
TEST(TrianglePrism, NeverRejectsWhatTheProjectionCovers) {
  RandomTriangle draw(7);
  Patch& patch = draw.patch;
  int covered = 0, prefiltered = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const double scale = std::pow(10.0, 3.0 * draw.u());
    const Vec3 offset = 100.0 * scale * draw.vec();
    patch.positions = {offset + scale * draw.vec(), offset + scale * draw.vec(), offset + scale * draw.vec()};
    if (trial % 50 == 0) patch.positions[2] = patch.positions[1];  // degenerate
    const double tolerance = scale * 0.2 * (1.0 + draw.u());
    const TrianglePrism prism(patch, patch.triangles[0], tolerance);
    const Vec3 tn = (patch.positions[1] - patch.positions[0]).cross(patch.positions[2] - patch.positions[0]);
    const Vec3 n = tn.squaredNorm() > 0.0 ? tn.normalized() : Vec3::UnitZ();
    for (int k = 0; k < 50; ++k) {
      // A point of the triangle's plane (barycentric coordinates up to a
      // little outside), then lifted along the normal up to about the
      // tolerance.
      Vec3 l(draw.u(), draw.u(), 0.0);
      l.z() = 1.0 - l.x() - l.y();
      if (k % 2) l *= 1.0 + 1e-3 * draw.u();
      const Vec3 p = l.x() * patch.positions[0] + l.y() * patch.positions[1] + l.z() * patch.positions[2];
      const Vec3 q = p + (k % 3 ? 1.0 : 1.0 + 1e-9) * tolerance * draw.u() * n;
      Vec3 bary;
      double dist2;
      const bool full = project_to_patch_triangle(patch, patch.triangles[0], q, n, tolerance, bary, dist2);
      const bool may = prism.may_cover(q);
      ASSERT_TRUE(may || !full) << "trial " << trial << " point " << k;
      // The same tests as half-spaces (the synthesis' row spans), up to rounding.
      std::array<TrianglePrism::HalfSpace, 5> half_spaces;
      bool everything = false;
      if (prism.half_spaces(half_spaces, everything)) {
        const double eps = 1e-9 * (scale + offset.norm());
        bool inside_loose = true, inside_strict = true;
        for (const auto& h : half_spaces) {
          const double v = h.n.dot(q) - h.c;
          inside_loose = inside_loose && v >= -eps;
          inside_strict = inside_strict && v >= eps;
        }
        ASSERT_TRUE(!may || inside_loose) << "trial " << trial << " point " << k;
        ASSERT_TRUE(!inside_strict || may) << "trial " << trial << " point " << k;
      } else {
        ASSERT_EQ(may, everything) << "trial " << trial;
      }
      covered += full;
      prefiltered += !may;
    }
  }
  // Both outcomes occur often enough for the check to mean something.
  EXPECT_GT(covered, 5000);
  EXPECT_GT(prefiltered, 20000);
}

// project_to_patch_triangle against its definition, the slack test by the
// closest point of the triangle for every point outside it (project() skips
// that search where an edge's line alone puts the point beyond the slack).
// Points are drawn in a band of a few slacks around random triangles, where
// both answers occur.
TEST(TriangleProjection, CoversWhatItsClosestPointPutsWithinTheSlack) {
  RandomTriangle draw(5);
  Patch& patch = draw.patch;
  int inside = 0, in_slack = 0, beyond = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    const double scale = std::pow(10.0, 2.0 * draw.u());
    patch.positions = {scale * draw.vec(), scale * draw.vec(), scale * draw.vec()};
    if (trial % 3 == 0)
      patch.positions[2] =
          patch.positions[0] + 0.02 * scale * draw.vec() + 0.5 * (patch.positions[1] - patch.positions[0]);  // a sliver
    const double tolerance = scale * 0.3 * (1.5 + draw.u());
    const double slack = projection_slack(tolerance);
    const Vec3& a = patch.positions[0];
    const Vec3& b = patch.positions[1];
    const Vec3& c = patch.positions[2];
    const Vec3 n = (b - a).cross(c - a).normalized();
    for (int k = 0; k < 100; ++k) {
      // A point of the triangle's plane near an edge or a corner, lifted
      // within the tolerance.
      Vec3 l(draw.u(), draw.u(), 0.0);
      l = 0.5 * (l + Vec3::Constant(1.0 / 3.0));
      l.z() = 1.0 - l.x() - l.y();
      const Vec3 on_plane = l.x() * a + l.y() * b + l.z() * c + 4.0 * slack * draw.u() * (b - a).normalized();
      const Vec3 q = on_plane + 0.9 * tolerance * draw.u() * n;
      const Vec3 qp = q - n * n.dot(q - a);
      const Vec3 closest = interpolate(barycentric(qp, a, b, c), a, b, c);
      const double out = (closest - qp).norm();
      if (std::abs(out - slack) < 1e-9 * scale) continue;  // on the border: rounding decides
      Vec3 bary;
      double dist2;
      const bool covered = project_to_patch_triangle(patch, patch.triangles[0], q, n, tolerance, bary, dist2);
      ASSERT_EQ(covered, out <= slack) << "trial " << trial << " point " << k << ": " << out / slack << " slacks out";
      const bool in = out < 1e-9 * scale;
      inside += in, in_slack += !in && out <= slack, beyond += out > slack;
    }
  }
  EXPECT_GT(inside, 10000);
  EXPECT_GT(in_slack, 1000);
  EXPECT_GT(beyond, 10000);
}

// TriangleProjection::OnPlane (the synthesis' projected fallback over one
// surface face, whose points and normals are affine in atlas coordinates)
// gives project()'s answers at those points: the same points covered, the
// same barycentric coordinates and distances up to rounding. Faces are
// drawn through random triangles at random tilts, their normals varying
// across them, so that all of project()'s tests (facing, tolerance, inside,
// slack) decide some of the points.
TEST(TriangleProjection, OnAFacePlaneAgreesWithThePerPointProjection) {
  RandomTriangle draw(11);
  Patch& patch = draw.patch;
  int covered = 0, rejected = 0, differ = 0, slack = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    const double scale = std::pow(10.0, 2.0 * draw.u());
    const Vec3 offset = 10.0 * scale * draw.vec();
    patch.positions = {offset + scale * draw.vec(), offset + scale * draw.vec(), offset + scale * draw.vec()};
    const double tolerance = scale * 0.1 * (1.5 + draw.u());
    const TriangleProjection projection(patch, patch.triangles[0], tolerance);
    const Vec3 tn =
        (patch.positions[1] - patch.positions[0]).cross(patch.positions[2] - patch.positions[0]).normalized();
    // The face: through the triangle's centroid, tilted, spanned by two
    // atlas axes of about a hundredth of the triangle per texel.
    const Vec3 centre = (patch.positions[0] + patch.positions[1] + patch.positions[2]) / 3.0;
    const Vec3 tilt = (tn + 0.3 * draw.vec()).normalized();
    const Vec3 u = tilt.cross(draw.vec()).normalized(), v = tilt.cross(u);
    TriangleProjection::Affine3 plane{centre + 0.05 * scale * draw.u() * tilt, 0.01 * scale * u, 0.01 * scale * v};
    TriangleProjection::Affine3 normal{tilt + 0.5 * draw.vec(), 0.005 * draw.vec(), 0.005 * draw.vec()};
    if (trial % 10 == 0) normal.origin = -normal.origin;  // a face facing away
    const TriangleProjection::OnPlane on_plane(projection, plane, normal);
    ASSERT_TRUE(on_plane.valid());
    for (int k = 0; k < 100; ++k) {
      const double x = 150.0 * draw.u(), y = 150.0 * draw.u();
      Vec3 bary, bary_plane;
      double dist2 = 0.0, dist2_plane = 0.0;
      const Vec3 n = normal.at(x, y).normalized();
      const bool full = projection.project(plane.at(x, y), n, bary, dist2);
      const bool fast = on_plane.project(x, y, bary_plane, dist2_plane);
      if (full != fast) {
        ++differ;  // only where a test's two sides meet, within rounding
        continue;
      }
      if (!full) {
        ++rejected;
        continue;
      }
      ++covered;
      slack += bary.minCoeff() == 0.0;
      ASSERT_LT((bary - bary_plane).lpNorm<Eigen::Infinity>(), 1e-9) << "trial " << trial << " point " << k;
      ASSERT_NEAR(dist2, dist2_plane, 1e-9 * scale * scale) << "trial " << trial << " point " << k;
    }
  }
  EXPECT_LE(differ, 3);
  EXPECT_GT(covered, 4000);
  EXPECT_GT(rejected, 20000);
  EXPECT_GT(slack, 100);
}

}  // namespace
}  // namespace fluidtex
