#include "fluidtex/tracking/patch_locator.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "fluidtex/geometry/point_index.h"

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
  if (l0 >= -1e-9 && l1 >= -1e-9 && l2 >= -1e-9) {
    bary = Vec3(l0, l1, l2).cwiseMax(0.0);
    bary /= bary.sum();
    dist2 = (qp - q).squaredNorm();
    return true;
  }
  // Just outside: the closest point of the triangle, within the slack.
  bary = barycentric(qp, a_, b_, c_);  // clamped to the triangle
  const Vec3 closest = interpolate(bary, a_, b_, c_);
  if ((closest - qp).squaredNorm() > slack2_) return false;
  dist2 = (closest - q).squaredNorm();
  return true;
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

struct PatchCoverage::Bounds {
  std::vector<int> patch;  // patch index per centre
  std::vector<Vec3> centre;
  std::vector<double> radius;         // farthest vertex + tolerance
  std::vector<std::size_t> tri_base;  // per entry: first of its triangles in tri_*
  std::vector<int> tri;               // triangle index per entry
  std::vector<Vec3> tri_centre;
  std::vector<double> tri_reach;  // farthest corner + tolerance
  double max_radius = 0.0;
  std::unique_ptr<PointIndex> index;
};

PatchCoverage::PatchCoverage(const std::vector<Patch>& patches, double tolerance, const std::vector<char>* include)
    : patches_(&patches), tolerance_(tolerance), bounds_(std::make_unique<Bounds>()) {
  Bounds& B = *bounds_;
  for (std::size_t p = 0; p < patches.size(); ++p) {
    if ((include && !(*include)[p]) || patches[p].positions.empty()) continue;
    B.patch.push_back(static_cast<int>(p));
  }
  const std::size_t m = B.patch.size();
  B.centre.resize(m);
  B.radius.resize(m);
  std::vector<std::vector<int>> tris(m);
  std::vector<std::vector<std::pair<Vec3, double>>> spheres(m);
  tbb::parallel_for(std::size_t(0), m, [&](std::size_t k) {
    const Patch& patch = patches[B.patch[k]];
    Vec3 c = Vec3::Zero();
    for (const Vec3& v : patch.positions) c += v;
    c /= static_cast<double>(patch.positions.size());
    double r = 0.0;
    for (const Vec3& v : patch.positions) r = std::max(r, (v - c).norm());
    B.centre[k] = c;
    B.radius[k] = r + tolerance;
    for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
      const Tri& tri = patch.triangles[t];
      const Vec3 tc = (patch.positions[tri[0]] + patch.positions[tri[1]] + patch.positions[tri[2]]) / 3.0;
      double reach = 0.0;
      for (int j = 0; j < 3; ++j) reach = std::max(reach, (patch.positions[tri[j]] - tc).norm());
      tris[k].push_back(static_cast<int>(t));
      spheres[k].emplace_back(tc, reach + tolerance);
    }
  });
  B.tri_base.assign(m + 1, 0);
  for (std::size_t k = 0; k < m; ++k) {
    B.tri_base[k + 1] = B.tri_base[k] + tris[k].size();
    B.tri.insert(B.tri.end(), tris[k].begin(), tris[k].end());
    for (const auto& [c, r] : spheres[k]) {
      B.tri_centre.push_back(c);
      B.tri_reach.push_back(r);
    }
    B.max_radius = std::max(B.max_radius, B.radius[k]);
  }
  B.index = std::make_unique<PointIndex>(B.centre);
}

namespace {

/// Weight of `patch` at p on its nearest triangle among those `candidate`
/// accepts (lowest index on a tie), 0 when p projects onto none.
template <class Candidate>
double nearest_weight(const Patch& patch, const Vec3& p, const Vec3& n, double tolerance, Candidate&& candidate) {
  double best = std::numeric_limits<double>::infinity();
  double weight = 0.0;
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    if (!candidate(t)) continue;
    const Tri& tri = patch.triangles[t];
    Vec3 bary;
    double dist2;
    if (!project_to_patch_triangle(patch, tri, p, n, tolerance, bary, dist2) || !(dist2 < best)) continue;
    best = dist2;
    weight = interpolate(patch.weight, tri, bary);
  }
  return weight;
}

}  // namespace

bool patch_covers(const Patch& patch, const Vec3& p, const Vec3& n, double tolerance) {
  return nearest_weight(patch, p, n, tolerance, [](std::size_t) { return true; }) > 0.0;
}

PatchCoverage::~PatchCoverage() = default;

bool PatchCoverage::covers(const Vec3& p, const Vec3& n) const {
  const Bounds& B = *bounds_;
  if (B.patch.empty()) return false;
  std::vector<std::pair<double, int>> near;
  for (int k : B.index->within(p, B.max_radius)) {
    const double d2 = (B.centre[k] - p).squaredNorm();
    if (d2 <= B.radius[k] * B.radius[k]) near.emplace_back(d2, k);
  }
  std::sort(near.begin(), near.end());
  for (const auto& [d2, k] : near) {
    // As locate(): the patch's nearest triangle (lowest index on a tie) decides.
    // B.tri lists every triangle of the patch in order, so triangle t is entry
    // tri_base[k] + t.
    const std::size_t base = B.tri_base[k];
    auto near_p = [&](std::size_t t) {
      return (B.tri_centre[base + t] - p).squaredNorm() <= B.tri_reach[base + t] * B.tri_reach[base + t];
    };
    if (nearest_weight((*patches_)[B.patch[k]], p, n, tolerance_, near_p) > 0.0) return true;
  }
  return false;
}

std::vector<char> uncovered_faces(const SurfaceIndex& surface, const PatchCoverage& coverage) {
  const std::size_t nf = surface.mesh().triangles.size();
  std::vector<char> bare(nf, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nf), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t f = r.begin(); f != r.end(); ++f) {
      const SurfacePoint s = surface.at(static_cast<int>(f), Vec3::Constant(1.0 / 3.0));
      bare[f] = !coverage.covers(s.position, surface.normal_at(s));
    }
  });
  return bare;
}

double uncovered_area_fraction(const SurfaceIndex& surface, const PatchCoverage& coverage) {
  const std::vector<char> uncovered = uncovered_faces(surface, coverage);
  double total = 0.0, bare = 0.0;  // summed in face order: deterministic
  for (std::size_t f = 0; f < uncovered.size(); ++f) {
    total += surface.face_areas()[f];
    if (uncovered[f]) bare += surface.face_areas()[f];
  }
  return total > 0.0 ? bare / total : 0.0;
}

}  // namespace fluidtex

namespace fluidtex {

std::vector<char> uncovered_samples(const std::vector<SurfaceSample>& samples, const PatchCoverage& coverage) {
  std::vector<char> bare(samples.size(), 1);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples.size()), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      bare[i] = !coverage.covers(samples[i].point.position, samples[i].normal);
    }
  });
  return bare;
}

}  // namespace fluidtex
