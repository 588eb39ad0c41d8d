/// @file patch_coverage.h
/// @brief Whether the patches cover the surface: per point (PatchCoverage,
/// the same answer as PatchLocator's found the cheap way), per face
/// (bare_faces) and as the uncovered share of the area (the coverage measure
/// of the Poisson update and of eval).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "fluidtex/geometry/surface.h"
#include "fluidtex/tracking/patch.h"
#include "fluidtex/tracking/patch_locator.h"

namespace fluidtex {

/// Whether some patch covers a surface point with a positive weight: the same
/// answer as PatchLocator (any hit with w > 0), found the cheap way. Patches
/// are bounded by spheres (vertex centroid, farthest vertex) in a k-d tree
/// of a few thousand centres; the patches whose sphere reaches the point are
/// tried nearest first; in each, as in locate(), the nearest triangle the
/// point projects into (behind a centroid-distance reject) gives the weight.
/// The first patch with w > 0 answers. Most points are covered by their
/// nearest patch, so the answer usually comes after one patch, and no tree
/// is built over the millions of patch triangles.
/// True when `p` (normal `n`) projects onto `patch` within `tolerance` where
/// its weight is positive (the patch's nearest triangle decides, as in
/// PatchCoverage::covers).
bool patch_covers(const Patch& patch, const Vec3& p, const Vec3& n, double tolerance);

class PatchCoverage {
 public:
  PatchCoverage(const std::vector<Patch>& patches, double tolerance, const std::vector<char>* include = nullptr);
  ~PatchCoverage();
  bool covers(const Vec3& p, const Vec3& n) const;  ///< thread safe
  /// The same hits as PatchLocator::locate over the same patches and
  /// tolerance (every covering patch, its nearest triangle, in patch order),
  /// for a few points: no tree over the patch triangles is built. Thread safe.
  void locate(const Vec3& p, const Vec3& n, std::vector<PatchHit>& hits) const;
  /// locate() for each of `points` (unit normals `normals`) in turn, for
  /// points close together (one tile's texels), whose candidate patches and
  /// triangles are found once: `found(i, hits)` with point i's hits. Thread
  /// safe.
  void locate_each(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                   const std::function<void(std::size_t, std::vector<PatchHit>&)>& found) const;
  /// covers() for groups of points (group g: points[start[g] .. start[g + 1]),
  /// e.g. the samples of one face): `bare(g, i)` for each point i that no
  /// patch covers, in order within a group. Groups whose centroids share a
  /// cell about a patch triangle wide are tested together, their candidate
  /// patches and triangles found once. Thread safe; `bare` is called from
  /// several threads at once, for different groups.
  void uncovered_each(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                      const std::vector<std::size_t>& start,
                      const std::function<void(std::size_t, std::size_t)>& bare) const;
  /// The nearest point of any patch triangle facing `n` within `reach` of
  /// `p` (in-plane distance too, unlike locate()); false when there is none.
  /// Thread safe.
  bool nearest(const Vec3& p, const Vec3& n, double reach, PatchHit& hit) const;

 private:
  /// Whether bounded patch k covers p with w > 0.
  bool covers_with(std::size_t k, const Vec3& p, const Vec3& n) const;
  /// The bounded patches whose sphere reaches the ball (c, r), nearest first.
  std::vector<std::size_t> near(const Vec3& c, double r) const;
  struct Bounds;
  class Ball;
  const std::vector<Patch>* patches_;
  double tolerance_;
  std::unique_ptr<Bounds> bounds_;
};

/// Where coverage is tested on the surface: on each face, the centroids of
/// the n² triangles of its n-fold barycentric subdivision, n the smallest
/// count that brings the face's longest edge down to `spacing` (1, the
/// centroid alone, on faces smaller than that). On a coarse mesh the centroid
/// alone misses bare slivers inside a face that is covered at its centre.
struct FaceSamples {
  std::vector<int> count;          ///< per face: n
  std::vector<Vec3> bary;          ///< the samples of every face, face after face
  std::vector<std::size_t> start;  ///< samples of face f: bary[start[f] .. start[f + 1])
};
FaceSamples face_samples(const SurfaceIndex& surface, double spacing);

/// The faces of `surface` that some sample of `samples` finds bare (no patch
/// covers it with positive weight), ascending, and per such face its first
/// bare sample; with `faces`, only those faces are tested.
struct BareFaces {
  std::vector<int> face;
  std::vector<SurfaceSample> point;
};
BareFaces bare_faces(const SurfaceIndex& surface, const FaceSamples& samples, const PatchCoverage& coverage,
                     const std::vector<int>* faces = nullptr);

/// Fraction of the surface area with Σw = 0, tested at the samples of
/// face_samples(surface, spacing): each sample stands for its face's area
/// over n².
double uncovered_area_fraction(const SurfaceIndex& surface, const PatchCoverage& coverage, double spacing);

/// Per sample: 1 when no patch covers it with positive weight.
std::vector<char> uncovered_samples(const std::vector<SurfaceSample>& samples, const PatchCoverage& coverage);

}  // namespace fluidtex
