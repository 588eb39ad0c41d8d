#include "fluidtex/tracking/patch_locator.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <utility>

#include "fluidtex/geometry/point_index.h"
#include "fluidtex/util/parallel.h"

namespace fluidtex {

TriangleProjection::TriangleProjection(const Patch& patch, const Tri& t, double tolerance)
    : a_(patch.positions[t[0]]), b_(patch.positions[t[1]]), c_(patch.positions[t[2]]) {
  tn_ = (b_ - a_).cross(c_ - a_);
  tn2_ = tn_.squaredNorm();
  v0_ = b_ - a_, v1_ = c_ - a_;
  d00_ = v0_.dot(v0_), d01_ = v0_.dot(v1_), d11_ = v1_.dot(v1_);
  den_ = d00_ * d11_ - d01_ * d01_;
  tolerance2_ = tolerance * tolerance;
  const double slack = projection_slack(tolerance);
  slack2_ = slack * slack;
  // A point of the plane with l_k < 0 lies −l_k·h_k outside the line of the
  // edge opposite corner k (h_k the triangle's height over it), so at least
  // that far from the triangle: beyond the slack where −l_k·h_k > slack.
  // A hair looser (rounding), so that the closest point decides at the
  // border as before (settle).
  const double twice_area = std::sqrt(tn2_);
  const double edge[3] = {(c_ - b_).norm(), (a_ - c_).norm(), (b_ - a_).norm()};
  for (int k = 0; k < 3; ++k) far_[k] = -(1.0 + 1e-9) * slack * edge[k] / twice_area;
}

template <class Points>
bool TriangleProjection::settle(double l0, double l1, double l2, double inside_dist2, Points&& points, Vec3& bary,
                                double& dist2) const {
  if (l0 >= -1e-9 && l1 >= -1e-9 && l2 >= -1e-9) {
    bary = Vec3(l0, l1, l2).cwiseMax(0.0);
    bary /= bary.sum();
    dist2 = inside_dist2;
    return true;
  }
  if (l0 < far_[0] || l1 < far_[1] || l2 < far_[2]) return false;  // beyond the slack of an edge
  // Just outside: the closest point of the triangle, within the slack.
  const auto [q, qp] = points();
  bary = barycentric(qp, a_, b_, c_);  // clamped to the triangle
  const Vec3 closest = interpolate(bary, a_, b_, c_);
  if ((closest - qp).squaredNorm() > slack2_) return false;
  dist2 = (closest - q).squaredNorm();
  return true;
}

bool TriangleProjection::project(const Vec3& q, const Vec3& n, Vec3& bary, double& dist2) const {
  if (!(tn2_ > 0.0) || tn_.dot(n) <= 0.0) return false;  // degenerate, other side of a sheet, or a fold
  const double off = tn_.dot(q - a_) / tn2_;
  if (off * off * tn2_ > tolerance2_) return false;
  const Vec3 qp = q - tn_ * off;  // onto the triangle's plane
  const Vec3 v2 = qp - a_;
  const double d20 = v2.dot(v0_), d21 = v2.dot(v1_);
  if (!(den_ > 0.0)) return false;
  const double l1 = (d11_ * d20 - d01_ * d21) / den_, l2 = (d00_ * d21 - d01_ * d20) / den_, l0 = 1.0 - l1 - l2;
  return settle(
      l0, l1, l2, (qp - q).squaredNorm(), [&] { return std::pair(q, qp); }, bary, dist2);
}

TriangleProjection::OnPlane::OnPlane(const TriangleProjection& tri, const Affine3& q, const Affine3& n)
    : tri_(&tri), q_(q) {
  if (!(tri.tn2_ > 0.0) || !(tri.den_ > 0.0)) return;
  // Each of project()'s quantities is linear in q (or n): its value at the
  // origin, and its change per unit of x and of y.
  const auto linear = [](const Vec3& w, const Affine3& f, double at_origin) {
    return Affine{at_origin, w.dot(f.dx), w.dot(f.dy)};
  };
  facing_ = linear(tri.tn_, n, tri.tn_.dot(n.origin));
  off_ = linear(tri.tn_ / tri.tn2_, q, tri.tn_.dot(q.origin - tri.a_) / tri.tn2_);
  // l1 = (d11·(q − a)·v0 − d01·(q − a)·v1) / den, l2 likewise (project()
  // takes the dot products with the projection qp; v0, v1 lie in the plane).
  const Vec3 w1 = (tri.d11_ * tri.v0_ - tri.d01_ * tri.v1_) / tri.den_;
  const Vec3 w2 = (tri.d00_ * tri.v1_ - tri.d01_ * tri.v0_) / tri.den_;
  l1_ = linear(w1, q, w1.dot(q.origin - tri.a_));
  l2_ = linear(w2, q, w2.dot(q.origin - tri.a_));
  valid_ = true;
  for (const Affine* f : {&facing_, &off_, &l1_, &l2_}) valid_ = valid_ && std::isfinite(f->o + f->x + f->y);
  valid_ = valid_ && q.origin.allFinite() && q.dx.allFinite() && q.dy.allFinite();
}

bool TriangleProjection::OnPlane::project(double x, double y, Vec3& bary, double& dist2) const {
  const TriangleProjection& t = *tri_;
  if (facing_.at(x, y) <= 0.0) return false;  // other side of a sheet, or a fold
  const double off = off_.at(x, y);
  if (off * off * t.tn2_ > t.tolerance2_) return false;
  const double l1 = l1_.at(x, y), l2 = l2_.at(x, y), l0 = 1.0 - l1 - l2;
  const auto points = [&] {
    const Vec3 q = q_.at(x, y);
    return std::pair<Vec3, Vec3>(q, q - t.tn_ * off);
  };
  return t.settle(l0, l1, l2, off * off * t.tn2_, points, bary, dist2);
}

bool project_to_patch_triangle(const Patch& patch, const Tri& t, const Vec3& q, const Vec3& n, double tolerance,
                               Vec3& bary, double& dist2) {
  return TriangleProjection(patch, t, tolerance).project(q, n, bary, dist2);
}

TrianglePrism::TrianglePrism(const Patch& patch, const Tri& t, double tolerance) {
  for (int k = 0; k < 3; ++k) corner_[k] = patch.positions[t[k]];
  const Vec3 tn = (corner_[1] - corner_[0]).cross(corner_[2] - corner_[0]);
  degenerate_ = !(tn.squaredNorm() > 0.0);  // project_to_patch_triangle covers nothing
  if (degenerate_) return;
  normal_ = tn.normalized();
  double size = 0.0;
  for (int j = 0; j < 3; ++j) {
    const Vec3 edge = corner_[(j + 1) % 3] - corner_[j];
    inward_[j] = normal_.cross(edge).normalized();
    size = std::max(size, edge.norm());
  }
  // The margin (a millionth of the triangle and the tolerance) is far above
  // the rounding of either test and far below a texel.
  const double margin = 1e-6 * (size + tolerance);
  height_ = tolerance + margin;
  reach_ = projection_slack(tolerance) + margin;
  checked_ = std::isfinite(height_) && normal_.allFinite() && inward_[0].allFinite() && inward_[1].allFinite() &&
             inward_[2].allFinite();
}

// Triangles are kept in levels by size: level k holds the triangles whose
// centroid-to-corner reach is at most base·2^k, in a k-d tree over their
// centroids queried with radius tolerance + base·2^k. A few stretched
// triangles then cost only their own level instead of widening every query.
struct PatchLocator::Tree {
  struct Level {
    double reach = 0.0;
    std::vector<std::pair<int, int>> owner;  // (patch, triangle) per entry
    std::vector<Vec3> centres;
    std::unique_ptr<PointIndex> index;
  };
  std::vector<Level> levels;
};

PatchLocator::PatchLocator(const std::vector<Patch>& patches, double tolerance, const std::vector<char>* include)
    : patches_(&patches), tolerance_(tolerance), tree_(std::make_unique<Tree>()) {
  struct Entry {
    int patch, tri;
    Vec3 centre;
    double reach;
  };
  std::vector<Entry> entries;
  std::vector<double> reaches;
  for (std::size_t p = 0; p < patches.size(); ++p) {
    if (include && !(*include)[p]) continue;
    const Patch& patch = patches[p];
    for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
      const Tri& tri = patch.triangles[t];
      const Vec3 c = (patch.positions[tri[0]] + patch.positions[tri[1]] + patch.positions[tri[2]]) / 3.0;
      double reach = 0.0;
      for (int k = 0; k < 3; ++k) reach = std::max(reach, (patch.positions[tri[k]] - c).norm());
      entries.push_back({static_cast<int>(p), static_cast<int>(t), c, reach});
      reaches.push_back(reach);
    }
  }
  if (entries.empty()) return;
  // Base size: the median reach (most triangles land in the first level).
  std::nth_element(reaches.begin(), reaches.begin() + reaches.size() / 2, reaches.end());
  const double base = std::max(reaches[reaches.size() / 2], 1e-12);
  for (const Entry& e : entries) {
    std::size_t level = 0;
    while (base * std::ldexp(1.0, static_cast<int>(level)) < e.reach) ++level;
    if (tree_->levels.size() <= level) tree_->levels.resize(level + 1);
    Tree::Level& L = tree_->levels[level];
    L.reach = base * std::ldexp(1.0, static_cast<int>(level));
    L.owner.emplace_back(e.patch, e.tri);
    L.centres.push_back(e.centre);
  }
  for (Tree::Level& L : tree_->levels) L.index = std::make_unique<PointIndex>(L.centres);
}

PatchLocator::~PatchLocator() = default;

void PatchLocator::locate(const Vec3& p, const Vec3& n, std::vector<PatchHit>& hits) const {
  hits.clear();
  if (tree_->levels.empty()) return;
  const double h = tolerance_;
  struct Best {
    int patch, tri;
    double dist2;
    Vec3 bary;
  };
  std::vector<Best> best;
  // Any triangle within h of p has its centroid within h + reach of p.
  for (const Tree::Level& level : tree_->levels) {
    if (!level.index) continue;
    for (int e : level.index->within(p, h + level.reach)) {
      const auto [pi, ti] = level.owner[e];
      Vec3 bary;
      double dist2;
      if (!project_to_patch_triangle((*patches_)[pi], (*patches_)[pi].triangles[ti], p, n, h, bary, dist2)) continue;
      auto slot = std::find_if(best.begin(), best.end(), [p = pi](const Best& x) { return x.patch == p; });
      if (slot == best.end())
        best.push_back({pi, ti, dist2, bary});
      else if (dist2 < slot->dist2 || (dist2 == slot->dist2 && ti < slot->tri))
        *slot = {pi, ti, dist2, bary};
    }
  }
  std::sort(best.begin(), best.end(), [](const Best& x, const Best& y) { return x.patch < y.patch; });
  for (const Best& b : best) {
    const Patch& patch = (*patches_)[b.patch];
    const Tri& tri = patch.triangles[b.tri];
    PatchHit hit;
    hit.patch = b.patch;
    hit.tri = b.tri;
    hit.bary = b.bary;
    hit.uv = interpolate(patch.uvs, tri, b.bary);
    hit.weight = interpolate(patch.weight, tri, b.bary);
    hits.push_back(hit);
  }
}

}  // namespace fluidtex
