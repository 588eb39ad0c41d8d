#include "fluidtex/tracking/patch_coverage.h"

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

struct PatchCoverage::Bounds {
  std::vector<int> patch;  // patch index per centre
  std::vector<Vec3> centre;
  std::vector<double> radius;         // farthest vertex + tolerance
  std::vector<std::size_t> tri_base;  // per entry: first of its triangles in tri_*
  std::vector<int> tri;               // triangle index per entry
  std::vector<Vec3> tri_centre;
  std::vector<double> tri_reach;  // farthest corner + tolerance
  double max_radius = 0.0;
  double cell = 0.0;  // uncovered_each's grouping: the median triangle reach
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
  if (!B.tri_reach.empty()) {
    std::vector<double> reach = B.tri_reach;
    std::nth_element(reach.begin(), reach.begin() + reach.size() / 2, reach.end());
    B.cell = reach[reach.size() / 2];
  }
  B.index = std::make_unique<PointIndex>(B.centre);
}

namespace {

/// The nearest triangle of `patch` that p (normal `n`) projects onto among
/// those `candidate` accepts (lowest index on a tie, as PatchLocator::locate);
/// false when there is none.
template <class Candidate>
bool nearest_triangle(const Patch& patch, const Vec3& p, const Vec3& n, double tolerance, Candidate&& candidate,
                      int& nearest, Vec3& nearest_bary) {
  double best = std::numeric_limits<double>::infinity();
  nearest = -1;
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    if (!candidate(t)) continue;
    Vec3 bary;
    double dist2;
    if (!project_to_patch_triangle(patch, patch.triangles[t], p, n, tolerance, bary, dist2) || !(dist2 < best))
      continue;
    best = dist2;
    nearest = static_cast<int>(t);
    nearest_bary = bary;
  }
  return nearest >= 0;
}

/// Barycentric coordinates of the point of triangle (a, b, c) nearest to q,
/// a point of its plane: q itself inside, else the nearest point of the
/// nearest edge.
Vec3 nearest_in_plane(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 v0 = b - a, v1 = c - a, v2 = q - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1), d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double den = d00 * d11 - d01 * d01;
  if (den > 0.0) {
    const double l1 = (d11 * d20 - d01 * d21) / den, l2 = (d00 * d21 - d01 * d20) / den;
    if (l1 >= 0.0 && l2 >= 0.0 && l1 + l2 <= 1.0) return Vec3(1.0 - l1 - l2, l1, l2);
  }
  const std::array<Vec3, 3> corner{a, b, c};
  Vec3 best_bary = Vec3(1.0, 0.0, 0.0);
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const Vec3 &p0 = corner[k], &p1 = corner[(k + 1) % 3];
    const double len2 = (p1 - p0).squaredNorm();
    const double t = len2 > 0.0 ? std::clamp((q - p0).dot(p1 - p0) / len2, 0.0, 1.0) : 0.0;
    const double dist2 = (p0 + t * (p1 - p0) - q).squaredNorm();
    if (!(dist2 < best)) continue;
    best = dist2;
    best_bary = Vec3::Zero();
    best_bary[k] = 1.0 - t;
    best_bary[(k + 1) % 3] = t;
  }
  return best_bary;
}

/// Weight of `patch` at p on its nearest triangle, 0 when p projects onto none.
template <class Candidate>
double nearest_weight(const Patch& patch, const Vec3& p, const Vec3& n, double tolerance, Candidate&& candidate) {
  int t;
  Vec3 bary;
  if (!nearest_triangle(patch, p, n, tolerance, candidate, t, bary)) return 0.0;
  return interpolate(patch.weight, patch.triangles[t], bary);
}

}  // namespace

bool patch_covers(const Patch& patch, const Vec3& p, const Vec3& n, double tolerance) {
  return nearest_weight(patch, p, n, tolerance, [](std::size_t) { return true; }) > 0.0;
}

PatchCoverage::~PatchCoverage() = default;

bool PatchCoverage::covers_with(std::size_t k, const Vec3& p, const Vec3& n) const {
  const Bounds& B = *bounds_;
  // As locate(): the patch's nearest triangle (lowest index on a tie) decides.
  // B.tri lists every triangle of the patch in order, so triangle t is entry
  // tri_base[k] + t.
  const std::size_t base = B.tri_base[k];
  auto near_p = [&](std::size_t t) {
    return (B.tri_centre[base + t] - p).squaredNorm() <= B.tri_reach[base + t] * B.tri_reach[base + t];
  };
  return nearest_weight((*patches_)[B.patch[k]], p, n, tolerance_, near_p) > 0.0;
}

std::vector<std::size_t> PatchCoverage::near(const Vec3& c, double r) const {
  const Bounds& B = *bounds_;
  // Called per point by covers() and locate(): the scratch lists are kept
  // per thread.
  thread_local std::vector<int> within;
  thread_local std::vector<std::pair<double, std::size_t>> found;
  found.clear();
  B.index->within(c, B.max_radius + r, within);
  for (int k : within) {
    const double d2 = (B.centre[k] - c).squaredNorm();
    if (d2 <= (B.radius[k] + r) * (B.radius[k] + r)) found.emplace_back(d2, static_cast<std::size_t>(k));
  }
  std::sort(found.begin(), found.end());
  std::vector<std::size_t> out;
  out.reserve(found.size());
  for (const auto& f : found) out.push_back(f.second);
  return out;
}

bool PatchCoverage::covers(const Vec3& p, const Vec3& n) const {
  if (bounds_->patch.empty()) return false;
  for (std::size_t k : near(p, 0.0)) {
    if (covers_with(k, p, n)) return true;
  }
  return false;
}

/// The patches whose sphere reaches the ball (c, r) around a set of query
/// points close together (the samples of nearby faces, one tile's texels),
/// nearest first, and per patch, listed when it is first tried, its
/// triangles whose sphere reaches the ball with their projections: found
/// once for all the points instead of once per point.
class PatchCoverage::Ball {
 public:
  /// The ball around `points` (at least one).
  Ball(const PatchCoverage& coverage, const std::vector<Vec3>& points) : coverage_(&coverage) {
    c_ = Vec3::Zero();
    for (const Vec3& p : points) c_ += p;
    c_ /= static_cast<double>(points.size());
    r_ = 0.0;
    for (const Vec3& p : points) r_ = std::max(r_, (p - c_).norm());
    candidates_ = coverage.near(c_, r_);
    subsets_.resize(candidates_.size());
  }
  std::size_t size() const { return candidates_.size(); }
  /// The bounded index (PatchCoverage::Bounds) of candidate j.
  std::size_t bounded(std::size_t j) const { return candidates_[j]; }

  /// Whether candidate j's sphere holds p, and then the nearest of its
  /// triangles that p (normal n) projects onto (lowest index on a tie), as
  /// nearest_triangle over the whole patch: the triangles left out cannot
  /// reach any point of the ball. False when there is none.
  bool nearest(std::size_t j, const Vec3& p, const Vec3& n, int& nearest, Vec3& nearest_bary) {
    const Bounds& B = *coverage_->bounds_;
    const std::size_t k = candidates_[j];
    if ((B.centre[k] - p).squaredNorm() > B.radius[k] * B.radius[k]) return false;
    const std::size_t base = B.tri_base[k];
    Subset& sub = subsets_[j];
    if (!sub.listed) {
      sub.listed = true;
      const Patch& patch = (*coverage_->patches_)[B.patch[k]];
      for (std::size_t t = 0; t < B.tri_base[k + 1] - base; ++t) {
        const double reach = B.tri_reach[base + t] + r_;
        if ((B.tri_centre[base + t] - c_).squaredNorm() > reach * reach) continue;
        sub.tri.push_back(static_cast<int>(t));
        sub.projection.emplace_back(patch, patch.triangles[t], coverage_->tolerance_);
      }
    }
    double best = std::numeric_limits<double>::infinity();
    nearest = -1;
    for (std::size_t e = 0; e < sub.tri.size(); ++e) {
      const std::size_t t = static_cast<std::size_t>(sub.tri[e]);
      if ((B.tri_centre[base + t] - p).squaredNorm() > B.tri_reach[base + t] * B.tri_reach[base + t]) continue;
      Vec3 bary;
      double dist2;
      if (!sub.projection[e].project(p, n, bary, dist2) || !(dist2 < best)) continue;
      best = dist2;
      nearest = static_cast<int>(t);
      nearest_bary = bary;
    }
    return nearest >= 0;
  }

 private:
  struct Subset {
    bool listed = false;
    std::vector<int> tri;
    std::vector<TriangleProjection> projection;
  };
  const PatchCoverage* coverage_;
  Vec3 c_;
  double r_;
  std::vector<std::size_t> candidates_;
  std::vector<Subset> subsets_;
};

void PatchCoverage::locate_each(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                                const std::function<void(std::size_t, std::vector<PatchHit>&)>& found) const {
  const Bounds& B = *bounds_;
  std::vector<PatchHit> hits;
  if (B.patch.empty()) {
    for (std::size_t i = 0; i < points.size(); ++i) found(i, hits);
    return;
  }
  if (points.empty()) return;
  Ball ball(*this, points);
  for (std::size_t i = 0; i < points.size(); ++i) {
    hits.clear();
    for (std::size_t j = 0; j < ball.size(); ++j) {
      PatchHit hit;
      if (!ball.nearest(j, points[i], normals[i], hit.tri, hit.bary)) continue;
      const Patch& patch = (*patches_)[B.patch[ball.bounded(j)]];
      const Tri& tri = patch.triangles[hit.tri];
      hit.patch = B.patch[ball.bounded(j)];
      hit.uv = interpolate(patch.uvs, tri, hit.bary);
      hit.weight = interpolate(patch.weight, tri, hit.bary);
      hits.push_back(hit);
    }
    std::sort(hits.begin(), hits.end(), [](const PatchHit& x, const PatchHit& y) { return x.patch < y.patch; });
    found(i, hits);
  }
}

namespace {

/// Groups of points (group g: points[start[g] .. start[g+1])) in the order of
/// the cell of side `cell` that holds their centroid, groups in order within a
/// cell; a group whose centroid has no usable cell (or every group, without a
/// cell size) is a cell of its own.
struct CellOrder {
  std::vector<std::size_t> group;       ///< the groups, cell by cell
  std::vector<std::size_t> cell_start;  ///< cell c: group[cell_start[c] .. cell_start[c+1])
};

CellOrder order_by_cell(const std::vector<Vec3>& points, const std::vector<std::size_t>& start, double cell) {
  const std::size_t groups = start.size() - 1;
  using Key = std::array<std::int64_t, 4>;  // (own cell?, cell or group)
  std::vector<std::pair<Key, std::size_t>> keyed(groups);
  const bool by_cell = cell > 0.0 && std::isfinite(cell);
  parallel_each(groups, [&](std::size_t g) {
    Key key{1, static_cast<std::int64_t>(g), 0, 0};
    if (by_cell && start[g + 1] > start[g]) {
      Vec3 c = Vec3::Zero();
      for (std::size_t i = start[g]; i < start[g + 1]; ++i) c += points[i];
      const Vec3 q = (c / static_cast<double>(start[g + 1] - start[g]) / cell).array().floor();
      if (q.allFinite() && q.cwiseAbs().maxCoeff() < 0x1p52)
        key = {0, static_cast<std::int64_t>(q.x()), static_cast<std::int64_t>(q.y()), static_cast<std::int64_t>(q.z())};
    }
    keyed[g] = {key, g};
  });
  std::sort(keyed.begin(), keyed.end());
  CellOrder order;
  for (std::size_t k = 0; k < groups; ++k) {
    if (k == 0 || keyed[k].first != keyed[k - 1].first) order.cell_start.push_back(k);
    order.group.push_back(keyed[k].second);
  }
  order.cell_start.push_back(groups);
  return order;
}

}  // namespace

void PatchCoverage::uncovered_each(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                                   const std::vector<std::size_t>& start,
                                   const std::function<void(std::size_t, std::size_t)>& bare) const {
  const Bounds& B = *bounds_;
  if (start.size() < 2) return;
  const std::size_t groups = start.size() - 1;
  if (B.patch.empty()) {
    for (std::size_t g = 0; g < groups; ++g) {
      for (std::size_t i = start[g]; i < start[g + 1]; ++i) bare(g, i);
    }
    return;
  }
  const CellOrder order = order_by_cell(points, start, B.cell);
  const std::vector<std::size_t>& cell_start = order.cell_start;
  auto test_cell = [&](std::size_t c) {
    thread_local std::vector<Vec3> cell_points;  // kept per thread, as near()'s lists
    cell_points.clear();
    for (std::size_t k = cell_start[c]; k < cell_start[c + 1]; ++k) {
      const std::size_t g = order.group[k];
      cell_points.insert(cell_points.end(), points.begin() + static_cast<std::ptrdiff_t>(start[g]),
                         points.begin() + static_cast<std::ptrdiff_t>(start[g + 1]));
    }
    if (cell_points.empty()) return;
    Ball ball(*this, cell_points);
    // As covers_with(): the patch's nearest triangle (lowest index on a tie) decides.
    auto covers = [&](std::size_t j, const Vec3& p, const Vec3& n) {
      int t;
      Vec3 b;
      if (!ball.nearest(j, p, n, t, b)) return false;
      const Patch& patch = (*patches_)[B.patch[ball.bounded(j)]];
      return interpolate(patch.weight, patch.triangles[t], b) > 0.0;
    };
    for (std::size_t k = cell_start[c]; k < cell_start[c + 1]; ++k) {
      const std::size_t g = order.group[k];
      // Each point tries the patch that covered the point before it first.
      std::size_t last = ball.size();
      for (std::size_t i = start[g]; i < start[g + 1]; ++i) {
        bool covered = last < ball.size() && covers(last, points[i], normals[i]);
        for (std::size_t j = 0; j < ball.size() && !covered; ++j) {
          if (j == last || !covers(j, points[i], normals[i])) continue;
          covered = true;
          last = j;
        }
        if (!covered) bare(g, i);
      }
    }
  };
  parallel_each(cell_start.size() - 1, test_cell);
}

bool PatchCoverage::nearest(const Vec3& p, const Vec3& n, double reach, PatchHit& hit) const {
  const Bounds& B = *bounds_;
  double best = reach * reach;
  bool found = false;
  for (std::size_t k : near(p, reach)) {
    const Patch& patch = (*patches_)[B.patch[k]];
    const std::size_t base = B.tri_base[k];
    for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
      const double r = B.tri_reach[base + t] + reach;
      if ((B.tri_centre[base + t] - p).squaredNorm() > r * r) continue;
      const Tri& tri = patch.triangles[t];
      const Vec3 &a = patch.positions[tri[0]], &b = patch.positions[tri[1]], &c = patch.positions[tri[2]];
      const Vec3 tn = (b - a).cross(c - a);
      if (!(tn.dot(n) > 0.0)) continue;  // the other side of a sheet, a fold, degenerate
      const Vec3 bary = nearest_in_plane(p - tn * (tn.dot(p - a) / tn.squaredNorm()), a, b, c);
      const double dist2 = (interpolate(bary, a, b, c) - p).squaredNorm();
      if (!(dist2 < best)) continue;  // ties: the patch found first, its lower triangle
      best = dist2;
      found = true;
      hit.patch = B.patch[k];
      hit.tri = static_cast<int>(t);
      hit.bary = bary;
    }
  }
  if (!found) return false;
  const Patch& patch = (*patches_)[hit.patch];
  const Tri& tri = patch.triangles[hit.tri];
  hit.uv = interpolate(patch.uvs, tri, hit.bary);
  hit.weight = interpolate(patch.weight, tri, hit.bary);
  return true;
}

void PatchCoverage::locate(const Vec3& p, const Vec3& n, std::vector<PatchHit>& hits) const {
  const Bounds& B = *bounds_;
  hits.clear();
  if (B.patch.empty()) return;
  for (std::size_t k : near(p, 0.0)) {
    const std::size_t base = B.tri_base[k];
    auto near_p = [&](std::size_t t) {
      return (B.tri_centre[base + t] - p).squaredNorm() <= B.tri_reach[base + t] * B.tri_reach[base + t];
    };
    const Patch& patch = (*patches_)[B.patch[k]];
    PatchHit hit;
    if (!nearest_triangle(patch, p, n, tolerance_, near_p, hit.tri, hit.bary)) continue;
    const Tri& tri = patch.triangles[hit.tri];
    hit.patch = B.patch[k];
    hit.uv = interpolate(patch.uvs, tri, hit.bary);
    hit.weight = interpolate(patch.weight, tri, hit.bary);
    hits.push_back(hit);
  }
  std::sort(hits.begin(), hits.end(), [](const PatchHit& x, const PatchHit& y) { return x.patch < y.patch; });
}

FaceSamples face_samples(const SurfaceIndex& surface, double spacing) {
  const FrameMesh& mesh = surface.mesh();
  const std::size_t nf = mesh.triangles.size();
  FaceSamples out;
  out.count.resize(nf);
  out.start.assign(nf + 1, 0);
  for (std::size_t f = 0; f < nf; ++f) {
    const Tri& t = mesh.triangles[f];
    double longest = 0.0;
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, (mesh.positions[t[(k + 1) % 3]] - mesh.positions[t[k]]).norm());
    // Bounded so that a degenerate spacing or a huge face cannot exhaust memory.
    const double n = spacing > 0.0 ? std::ceil(longest / spacing) : 1.0;
    out.count[f] = static_cast<int>(std::clamp(std::isfinite(n) ? n : 1.0, 1.0, 64.0));
    out.start[f + 1] = out.start[f] + static_cast<std::size_t>(out.count[f]) * out.count[f];
  }
  out.bary.reserve(out.start.back());
  for (std::size_t f = 0; f < nf; ++f) {
    const int n = out.count[f];
    // Sub-triangle (i, j) upright: corners (i, j), (i+1, j), (i, j+1) in
    // steps of 1/n along the second and third barycentric; inverted:
    // (i+1, j), (i+1, j+1), (i, j+1).
    for (int i = 0; i < n; ++i) {
      for (int j = 0; i + j < n; ++j) {
        const double l1 = (i + 1.0 / 3.0) / n, l2 = (j + 1.0 / 3.0) / n;
        out.bary.emplace_back(1.0 - l1 - l2, l1, l2);
        if (i + j + 1 < n) {
          const double m1 = (i + 2.0 / 3.0) / n, m2 = (j + 2.0 / 3.0) / n;
          out.bary.emplace_back(1.0 - m1 - m2, m1, m2);
        }
      }
    }
  }
  return out;
}

namespace {

/// The samples of `faces` (the face order of FaceSamples), their points and
/// normals in one list, face after face: face k's from start[k] on.
struct SampleList {
  std::vector<Vec3> points, normals;
  std::vector<std::size_t> start;
};
SampleList sample_points(const SurfaceIndex& surface, const FaceSamples& samples, const std::vector<int>& faces) {
  SampleList out;
  out.start.assign(faces.size() + 1, 0);
  for (std::size_t k = 0; k < faces.size(); ++k)
    out.start[k + 1] = out.start[k] + (samples.start[faces[k] + 1] - samples.start[faces[k]]);
  out.points.resize(out.start.back());
  out.normals.resize(out.start.back());
  parallel_each(faces.size(), [&](std::size_t k) {
    const int f = faces[k];
    for (std::size_t s = samples.start[f], i = out.start[k]; s < samples.start[f + 1]; ++s, ++i) {
      const SurfacePoint p = surface.at(f, samples.bary[s]);
      out.points[i] = p.position;
      out.normals[i] = surface.normal_at(p);
    }
  });
  return out;
}

}  // namespace

BareFaces bare_faces(const SurfaceIndex& surface, const FaceSamples& samples, const PatchCoverage& coverage,
                     const std::vector<int>* faces) {
  std::vector<int> all;
  if (!faces) {
    all.resize(surface.mesh().triangles.size());
    std::iota(all.begin(), all.end(), 0);
    faces = &all;
  }
  // Per tested face, its first bare sample (−1: none).
  std::vector<std::ptrdiff_t> first(faces->size(), -1);
  const SampleList list = sample_points(surface, samples, *faces);
  coverage.uncovered_each(list.points, list.normals, list.start, [&](std::size_t k, std::size_t i) {
    if (first[k] < 0) first[k] = static_cast<std::ptrdiff_t>(samples.start[(*faces)[k]] + (i - list.start[k]));
  });
  BareFaces out;
  for (std::size_t k = 0; k < faces->size(); ++k) {
    if (first[k] < 0) continue;
    const int f = (*faces)[k];
    SurfaceSample sample;
    sample.point = surface.at(f, samples.bary[static_cast<std::size_t>(first[k])]);
    sample.normal = surface.normal_at(sample.point);
    out.face.push_back(f);
    out.point.push_back(sample);
  }
  return out;
}

double uncovered_area_fraction(const SurfaceIndex& surface, const PatchCoverage& coverage, double spacing) {
  const FaceSamples samples = face_samples(surface, spacing);
  const std::size_t nf = surface.mesh().triangles.size();
  std::vector<int> all(nf);
  std::iota(all.begin(), all.end(), 0);
  std::vector<int> bare(nf, 0);  // per face: bare samples
  const SampleList list = sample_points(surface, samples, all);
  coverage.uncovered_each(list.points, list.normals, list.start, [&](std::size_t f, std::size_t) { ++bare[f]; });
  double total = 0.0, uncovered = 0.0;  // summed in face order: deterministic
  for (std::size_t f = 0; f < nf; ++f) {
    const double area = surface.face_areas()[f];
    total += area;
    uncovered += area * bare[f] / static_cast<double>(samples.start[f + 1] - samples.start[f]);
  }
  return total > 0.0 ? uncovered / total : 0.0;
}

std::vector<char> uncovered_samples(const std::vector<SurfaceSample>& samples, const PatchCoverage& coverage) {
  // Each sample a group of its own: uncovered_each tests those of a cell
  // together.
  std::vector<Vec3> points(samples.size()), normals(samples.size());
  std::vector<std::size_t> start(samples.size() + 1);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    points[k] = samples[k].point.position;
    normals[k] = samples[k].normal;
    start[k + 1] = k + 1;
  }
  std::vector<char> bare(samples.size(), 0);
  coverage.uncovered_each(points, normals, start, [&](std::size_t k, std::size_t) { bare[k] = 1; });
  return bare;
}

}  // namespace fluidtex
