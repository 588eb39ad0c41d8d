#include "fluidtex/tracking/relaxation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <Eigen/Dense>  // JacobiSVD
#include <Eigen/Sparse>

#include "fluidtex/geometry/distortion.h"
#include "fluidtex/tracking/advection.h"

namespace fluidtex {

namespace {

/// The triangle of `uvs` over the origin (the disk centre) and the origin's
/// barycentric coordinates in it; the nearest triangle when none contains it.
bool locate_origin(const std::vector<Vec2>& uvs, const std::vector<Tri>& triangles, std::size_t& tri, Vec3& bary) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Tri& c = triangles[t];
    auto lift = [&](int v) { return Vec3(uvs[v].x(), uvs[v].y(), 0.0); };
    const Vec3 l = barycentric(Vec3::Zero(), lift(c[0]), lift(c[1]), lift(c[2]));  // clamped into the triangle
    const double d2 = interpolate(l, uvs[c[0]], uvs[c[1]], uvs[c[2]]).squaredNorm();
    if (d2 < best) best = d2, tri = t, bary = l;
  }
  return std::isfinite(best);
}

double disk_seen_weight(const Patch& patch, double radius) {
  double sum = 0.0;
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) sum += seen_weight(patch, t, radius);
  return sum;
}

/// The least-squares system of one local/global step in the manner of
/// as-rigid-as-possible flattening (Liu et al. 2008), started from the
/// current uv. Local: per triangle, the map J from its uv triangle to its
/// current 3D shape laid flat is A·Σ·Bᵀ (SVD); the target is the uv triangle
/// whose map has Σ clamped to [1/yield, yield], i.e. the uv edges times
/// B·Σ_c⁻¹·Σ·Bᵀ. A triangle within the yield keeps its uv edges. Global: the
/// edges' targets, cotangent-weighted (floored so that obtuse triangles keep
/// the system definite), plus a faint spring holding each vertex where it is,
/// which fixes the translation.
struct PlasticSystem {
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixX2d rhs;
  bool yielded = false;  ///< some triangle is beyond the yield
};

PlasticSystem plastic_system(const Patch& patch, double yield) {
  const std::size_t nv = patch.uvs.size();
  PlasticSystem sys;
  sys.entries.reserve(12 * patch.triangles.size() + nv);
  sys.rhs = Eigen::MatrixX2d::Zero(static_cast<Eigen::Index>(nv), 2);
  double scale = 0.0;
  for (const Tri& t : patch.triangles) {
    const RestTriangle p = rest_shape(patch.positions[t[0]], patch.positions[t[1]], patch.positions[t[2]]);
    const Vec2 u0 = patch.uvs[t[0]], u1 = patch.uvs[t[1]], u2 = patch.uvs[t[2]];
    const double area = signed_area(u0, u1, u2);
    if (!(area > 0.0)) continue;
    Eigen::Matrix2d uv_edges, flat_edges;
    uv_edges << u1 - u0, u2 - u0;
    flat_edges << p[1] - p[0], p[2] - p[0];
    Eigen::Matrix2d plastic = Eigen::Matrix2d::Identity();
    if (flat_edges.determinant() > 0.0) {
      const Eigen::JacobiSVD<Eigen::Matrix2d> svd(flat_edges * uv_edges.inverse(), Eigen::ComputeFullV);
      // A copy: through a reference GCC 12 sees Eigen's storage as maybe uninitialised.
      const Vec2 sigma = svd.singularValues();  // NOLINT(performance-unnecessary-copy-initialization)
      const Vec2 clamped = sigma.cwiseMax(1.0 / yield).cwiseMin(yield);
      sys.yielded = sys.yielded || clamped != sigma;
      plastic = svd.matrixV() * sigma.cwiseQuotient(clamped).asDiagonal() * svd.matrixV().transpose();
    }
    for (int k = 0; k < 3; ++k) {
      const int i = k, j = (k + 1) % 3, o = (k + 2) % 3;  // edge i–j, opposite corner o
      const Vec2 ei = patch.uvs[t[i]] - patch.uvs[t[o]], ej = patch.uvs[t[j]] - patch.uvs[t[o]];
      const double cot = ei.dot(ej) / (4.0 * area);  // ½ cot of the angle at o
      const double w = std::max(cot, 0.05);
      const int a = t[i], b = t[j];
      sys.entries.emplace_back(a, a, w), sys.entries.emplace_back(b, b, w);
      sys.entries.emplace_back(a, b, -w), sys.entries.emplace_back(b, a, -w);
      const Vec2 g = plastic * (patch.uvs[a] - patch.uvs[b]);
      sys.rhs.row(a) += w * g.transpose(), sys.rhs.row(b) -= w * g.transpose();
      scale += w;
    }
  }
  const double spring = 1e-10 * scale / static_cast<double>(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    sys.entries.emplace_back(static_cast<int>(v), static_cast<int>(v), spring);
    sys.rhs.row(static_cast<Eigen::Index>(v)) += spring * patch.uvs[v].transpose();
  }
  return sys;
}

/// `patch.uvs` moved `rate` of the way to `target` (translated so that the
/// point at uv 0 stays there), the step halved while it would fold a uv
/// triangle (the target of a crumpled patch can fold where its triangles'
/// shapes disagree); nullopt when even rate/8 folds one.
std::optional<std::vector<Vec2>> step_towards(const Patch& patch, const Eigen::MatrixX2d& target, double rate) {
  std::size_t tri = 0;
  Vec3 bary = Vec3::Zero();
  if (!locate_origin(patch.uvs, patch.triangles, tri, bary)) return std::nullopt;
  const Tri& c = patch.triangles[tri];
  const Vec2 centre = bary[0] * target.row(c[0]).transpose() + bary[1] * target.row(c[1]).transpose() +
                      bary[2] * target.row(c[2]).transpose();
  std::vector<Vec2> moved(patch.uvs.size());
  for (double step = rate; step >= rate / 8.0; step *= 0.5) {
    for (std::size_t v = 0; v < moved.size(); ++v) {
      const Vec2 to = target.row(static_cast<Eigen::Index>(v)).transpose();
      moved[v] = patch.uvs[v] + step * (to - centre - patch.uvs[v]);
    }
    const bool folds = std::any_of(patch.triangles.begin(), patch.triangles.end(), [&](const Tri& t) {
      return !(signed_area(moved[t[0]], moved[t[1]], moved[t[2]]) > 0.0);
    });
    if (!folds) return moved;
  }
  return std::nullopt;
}

}  // namespace

bool relax_patch(Patch& patch, double rate, double yield, const TrackingOptions& options) {
  if (patch.triangles.empty() || !(rate > 0.0)) return false;
  const PlasticSystem sys = plastic_system(patch, yield);
  if (!sys.yielded) return false;  // every triangle within the yield keeps its uv
  const auto nv = static_cast<Eigen::Index>(patch.uvs.size());
  Eigen::SparseMatrix<double> system(nv, nv);
  system.setFromTriplets(sys.entries.begin(), sys.entries.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(system);
  if (solver.info() != Eigen::Success) return false;
  const Eigen::MatrixX2d target = solver.solve(sys.rhs);
  if (solver.info() != Eigen::Success || !target.allFinite()) return false;
  std::optional<std::vector<Vec2>> moved = step_towards(patch, target, rate);
  if (!moved) return false;

  const double before = disk_seen_weight(patch, options.d());
  patch.uvs = std::move(*moved);
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    const Tri& k = patch.triangles[t];
    patch.rest[t] = {patch.uvs[k[0]], patch.uvs[k[1]], patch.uvs[k[2]]};
  }
  const double after = disk_seen_weight(patch, options.d());
  if (before > 0.0) patch.disk_weight *= after / before;
  return true;
}

}  // namespace fluidtex
