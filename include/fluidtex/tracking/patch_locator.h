/// @file patch_locator.h
/// @brief Which patches cover a point of the surface, and with which uv and
/// weight: the exact, per-point projection through the patch triangles that
/// Gagnon et al. 2019 (Sec. 7.1) use per texel, with a k-d tree over the
/// centroids of every patch triangle. Used as the reference ("exact") texel
/// synthesis; patch_coverage.h answers the cheaper question whether a point
/// is covered at all.
#pragma once

#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include "fluidtex/tracking/patch.h"

namespace fluidtex {

struct PatchHit {
  int patch = -1;  ///< index into the patch list given to the locator
  Vec2 uv = Vec2::Zero();
  double weight = 0.0;       ///< barycentric blend of the vertex weights w_V
  int tri = -1;              ///< the patch triangle that covers the point
  Vec3 bary = Vec3::Zero();  ///< and the point's barycentric coordinates in it
};

/// How far outside a patch triangle, in its plane, a point still counts as
/// covered by it: a tenth of the projection tolerance.
inline double projection_slack(double tolerance) { return 0.1 * tolerance; }

/// Projects the surface point `q` (unit normal `n`) onto triangle `t` of
/// `patch`: it covers q when it faces the same side (a triangle facing away is
/// the other side of a thin sheet, or a fold), lies within `tolerance` of q
/// along its normal, and contains q's projection up to an in-plane slack of
/// projection_slack() (so the corners of a polygonal rim between two patch border
/// points still count). On success, `bary` holds the (clamped) barycentric
/// coordinates and `dist2` the squared distance to q.
bool project_to_patch_triangle(const Patch& patch, const Tri& t, const Vec3& q, const Vec3& n, double tolerance,
                               Vec3& bary, double& dist2);

/// project_to_patch_triangle for one triangle and many points: what depends
/// only on the triangle is computed once (the same arithmetic, so the same
/// results).
class TriangleProjection {
 public:
  TriangleProjection(const Patch& patch, const Tri& t, double tolerance);
  bool project(const Vec3& q, const Vec3& n, Vec3& bary, double& dist2) const;

  /// A Vec3 that is an affine function of two coordinates (x, y):
  /// origin + x·dx + y·dy (the points of a flat surface face over its atlas
  /// texels, or their interpolated normals before normalisation).
  struct Affine3 {
    Vec3 origin, dx, dy;
    Vec3 at(double x, double y) const { return origin + x * dx + y * dy; }
  };

  /// project() for the points `q` of one flat face, with normals `n` (any
  /// positive scale), both affine in (x, y). Every quantity project() tests
  /// is then affine in (x, y) too: the signed distance along the triangle's
  /// normal, the barycentric coordinates of the projection and the facing
  /// test are set up once per face, and a point costs a few multiply-adds.
  /// Only points just outside the triangle (within the slack) take the
  /// closest-point search. The same results as project() at q(x, y), n(x, y)
  /// up to rounding.
  class OnPlane {
   public:
    OnPlane(const TriangleProjection& tri, const Affine3& q, const Affine3& n);
    bool valid() const { return valid_; }  ///< false: the triangle is degenerate or a coefficient non-finite
    bool project(double x, double y, Vec3& bary, double& dist2) const;

   private:
    struct Affine {
      double o = 0.0, x = 0.0, y = 0.0;
      double at(double px, double py) const { return o + px * x + py * y; }
    };
    const TriangleProjection* tri_;
    Affine3 q_;
    Affine facing_, off_, l1_, l2_;  // tn·n, off (tn units), l1, l2
    bool valid_ = false;
  };

 private:
  /// project()'s last step, once a point's barycentrics (l0, l1, l2) on the
  /// triangle's plane are known: inside (up to rounding; `inside_dist2` is
  /// then its squared distance), beyond the slack of an edge, or else
  /// within the slack if the triangle's closest point is, found from the
  /// point and its projection on the plane that `points()` returns.
  template <class Points>
  bool settle(double l0, double l1, double l2, double inside_dist2, Points&& points, Vec3& bary, double& dist2) const;

  Vec3 a_, b_, c_, tn_, v0_, v1_;
  double tn2_, d00_, d01_, d11_, den_, tolerance2_, slack2_;
  Vec3 far_;  // per corner k: the barycentric l_k below which a point lies beyond the slack
};

/// A cheaper, conservative form of project_to_patch_triangle's tests for one
/// triangle tested against many points: `may_cover(q)` is false only where
/// project_to_patch_triangle is false (q farther than the tolerance from the
/// triangle's plane, or its projection farther than the slack outside an
/// edge), up to a margin well above rounding. Four dot products per point
/// instead of a projection, and no closest-point search for the many points
/// just outside.
class TrianglePrism {
 public:
  TrianglePrism(const Patch& patch, const Tri& t, double tolerance);
  bool may_cover(const Vec3& q) const {
    if (!checked_) return !degenerate_;
    if (std::abs((q - corner_[0]).dot(normal_)) > height_) return false;
    for (int j = 0; j < 3; ++j) {
      if ((q - corner_[j]).dot(inward_[j]) < -reach_) return false;
    }
    return true;
  }

  /// may_cover's tests as half-spaces: q passes where n·q ≥ c for each.
  struct HalfSpace {
    Vec3 n;
    double c;
  };
  /// False where may_cover is constant: then `everything` says which.
  bool half_spaces(std::array<HalfSpace, 5>& out, bool& everything) const {
    everything = !degenerate_;
    if (!checked_) return false;
    const double h = corner_[0].dot(normal_);
    out[0] = {normal_, h - height_};
    out[1] = {-normal_, -h - height_};
    for (int j = 0; j < 3; ++j) out[2 + j] = {inward_[j], corner_[j].dot(inward_[j]) - reach_};
    return true;
  }

 private:
  bool degenerate_ = false;  // zero area: covers nothing
  bool checked_ = false;     // false: every point goes to the full test (non-finite corners)
  Vec3 normal_;
  std::array<Vec3, 3> corner_, inward_;  // edge j runs from corner j to j + 1
  double height_ = 0.0, reach_ = 0.0;
};

class PatchLocator {
 public:
  /// `tolerance`: how far (scene units) a patch triangle may lie from the
  /// query point and still cover it (patch triangles are flat chords of a
  /// curved surface, so a little slack is needed; a fraction of mpt).
  /// With `include`, only the patches whose entry is non-zero are located.
  PatchLocator(const std::vector<Patch>& patches, double tolerance, const std::vector<char>* include = nullptr);
  ~PatchLocator();

  /// The covering patches of the surface point `p` with unit normal `n`, at
  /// most one hit per patch (its nearest triangle), in patch order. A
  /// triangle facing away from `n` (the other side of a thin sheet) does
  /// not cover. Thread safe.
  void locate(const Vec3& p, const Vec3& n, std::vector<PatchHit>& hits) const;

 private:
  struct Tree;
  const std::vector<Patch>* patches_;
  double tolerance_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace fluidtex
