#include "fluidtex/tracking/orientation.h"

#include <cmath>

#include <Eigen/Geometry>  // Rotation2D

#include "fluidtex/geometry/point_index.h"
#include "fluidtex/util/random.h"

namespace fluidtex {

Vec3 u_axis(const Patch& patch, const Tri& t) {
  const Vec2 e1 = patch.uvs[t[1]] - patch.uvs[t[0]], e2 = patch.uvs[t[2]] - patch.uvs[t[0]];
  const Vec3 E1 = patch.positions[t[1]] - patch.positions[t[0]], E2 = patch.positions[t[2]] - patch.positions[t[0]];
  const double det = e1.x() * e2.y() - e2.x() * e1.y();
  if (!(std::abs(det) > 0.0)) return Vec3::Zero();
  // The triangle's affine map uv → 3D is J = [E1 E2]·[e1 e2]⁻¹; ∂x/∂u is its first column.
  const Vec3 a = (E1 * e2.y() - E2 * e1.y()) / det;
  return a.allFinite() ? a : Vec3::Zero();
}

Vec2 uv_of(const Patch& patch, const Tri& t, const Vec3& a) {
  const Vec3 E1 = patch.positions[t[1]] - patch.positions[t[0]], E2 = patch.positions[t[2]] - patch.positions[t[0]];
  // a ≈ α·E1 + β·E2 in the least-squares sense (the normal part dropped),
  // which the chart maps to α·e1 + β·e2.
  const double g11 = E1.dot(E1), g12 = E1.dot(E2), g22 = E2.dot(E2);
  const double det = g11 * g22 - g12 * g12;
  if (!(det > 0.0)) return Vec2::Zero();
  const double r1 = E1.dot(a), r2 = E2.dot(a);
  const double alpha = (g22 * r1 - g12 * r2) / det, beta = (g11 * r2 - g12 * r1) / det;
  const Vec2 uv = alpha * (patch.uvs[t[1]] - patch.uvs[t[0]]) + beta * (patch.uvs[t[2]] - patch.uvs[t[0]]);
  return uv.allFinite() ? uv : Vec2::Zero();
}

Vec3 world_direction(Axis axis, const Vec3& n) {
  const double cos30 = std::sqrt(3.0) / 2.0;
  Vec3 e = Vec3::Unit(static_cast<int>(axis));
  if (std::abs(e.dot(n)) > cos30) e = Vec3::Unit((static_cast<int>(axis) + 1) % 3);
  const Vec3 tangent = e - e.dot(n) * n;
  return tangent.squaredNorm() > 0.0 ? Vec3(tangent.normalized()) : e;
}

void turn_uv(Patch& patch, double angle) {
  const Eigen::Rotation2Dd turn(angle);
  for (Vec2& uv : patch.uvs) uv = turn * uv;
}

namespace {

/// The triangles of a patch inside its disk (uv centroid within d), each
/// with its area times K_S's radial term: how much it shows.
struct DiskTriangles {
  std::vector<std::size_t> index;
  std::vector<double> weight;
};

DiskTriangles disk_triangles(const Patch& patch, double d) {
  DiskTriangles disk;
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    const Tri& tri = patch.triangles[t];
    const Vec2 centroid = (patch.uvs[tri[0]] + patch.uvs[tri[1]] + patch.uvs[tri[2]]) / 3.0;
    const double radial = 1.0 - centroid.norm() / d;
    const double w = triangle_area(patch.positions, tri) * radial;
    if (!(w > 0.0)) continue;
    disk.index.push_back(t);
    disk.weight.push_back(w);
  }
  return disk;
}

/// Σ weight·(unit direction) of the u axes of the live patches over the
/// disk's triangles, each carried into `fresh`'s uv.
Vec2 field_sum(const Patch& fresh, const DiskTriangles& disk, const OrientationContext& context) {
  if (!context.coverage) return Vec2::Zero();
  std::vector<Vec3> points, normals;
  for (std::size_t t : disk.index) {
    const Tri& tri = fresh.triangles[t];
    const Vec3 &a = fresh.positions[tri[0]], &b = fresh.positions[tri[1]], &c = fresh.positions[tri[2]];
    points.emplace_back((a + b + c) / 3.0);
    const Vec3 n = (b - a).cross(c - a);
    normals.push_back(n.squaredNorm() > 0.0 ? Vec3(n.normalized()) : fresh.centre.normal);
  }
  std::vector<Vec2> per_point(points.size(), Vec2::Zero());
  context.coverage->locate_each(points, normals, [&](std::size_t i, std::vector<PatchHit>& hits) {
    const Tri& tri = fresh.triangles[disk.index[i]];
    for (const PatchHit& h : hits) {  // in patch order
      const Patch& other = context.live[static_cast<std::size_t>(h.patch)];
      const Vec2 along = uv_of(fresh, tri, u_axis(other, other.triangles[static_cast<std::size_t>(h.tri)]));
      if (h.weight > 0.0 && along.squaredNorm() > 0.0) per_point[i] += h.weight * along.normalized();
    }
  });
  Vec2 sum = Vec2::Zero();
  for (std::size_t i = 0; i < per_point.size(); ++i) sum += disk.weight[i] * per_point[i];
  return sum;
}

/// Σ weight·(direction) of the 3D field `along(t)` over the disk's
/// triangles, carried into `fresh`'s uv (unit directions when `unit`).
template <class Along>
Vec2 carried_sum(const Patch& fresh, const DiskTriangles& disk, Along&& along, bool unit) {
  Vec2 sum = Vec2::Zero();
  for (std::size_t i = 0; i < disk.index.size(); ++i) {
    const Tri& tri = fresh.triangles[disk.index[i]];
    const Vec2 uv = uv_of(fresh, tri, along(tri));
    if (!(uv.squaredNorm() > 0.0)) continue;
    sum += disk.weight[i] * (unit ? Vec2(uv.normalized()) : uv);
  }
  return sum;
}

/// Σ weight·(velocity) over the disk, carried into `fresh`'s uv; zero where
/// the disk moves less than kFlowOrientationMotion·d a frame.
Vec2 flow_sum(const Patch& fresh, const DiskTriangles& disk, const OrientationContext& context, double d) {
  const auto velocity = [&](const Tri& tri) {
    Vec3 v = Vec3::Zero();
    for (int k = 0; k < 3; ++k) v += context.surface.velocity_at(fresh.projections[tri[k]]);
    return Vec3(v / 3.0);
  };
  double sum_w = 0.0;
  Vec3 mean = Vec3::Zero();
  for (std::size_t i = 0; i < disk.index.size(); ++i) {
    mean += disk.weight[i] * velocity(fresh.triangles[disk.index[i]]);
    sum_w += disk.weight[i];
  }
  if (!(sum_w > 0.0)) return Vec2::Zero();
  mean /= sum_w;
  const Vec3& n = fresh.centre.normal;
  const Vec3 tangential = mean - mean.dot(n) * n;
  if (!(tangential.norm() * context.dt >= kFlowOrientationMotion * d)) return Vec2::Zero();
  return carried_sum(fresh, disk, velocity, true);
}

}  // namespace

double orientation_angle(const Patch& fresh, const OrientationContext& context, const TrackingOptions& options) {
  if (options.orientation == Orientation::Random) return 0.0;
  const DiskTriangles disk = disk_triangles(fresh, options.d());
  Vec2 target = Vec2::Zero();
  if (options.orientation == Orientation::Flow) target = flow_sum(fresh, disk, context, options.d());
  if (!(target.squaredNorm() > 0.0)) target = field_sum(fresh, disk, context);
  if (!(target.squaredNorm() > 0.0)) {
    // No live patch over it: the world axis, chosen once at the centre so
    // that the whole patch follows the same one.
    const Vec3 axis = world_direction(options.orientation_axis, fresh.centre.normal);
    target = carried_sum(
        fresh, disk, [&axis](const Tri&) -> const Vec3& { return axis; }, false);
  }
  // The target direction lies at angle φ in the patch's uv; turning the uv
  // by −φ puts it along u.
  return target.squaredNorm() > 0.0 ? -std::atan2(target.y(), target.x()) : 0.0;
}

double anchor_distance(const Vec2& a, const Vec2& b) {
  const auto wrapped = [](double t) {
    const double f = std::abs(t - std::floor(t));
    return std::min(f, 1.0 - f);
  };
  return std::hypot(wrapped(a.x() - b.x()), wrapped(a.y() - b.y()));
}

void separate_anchors(const std::vector<Patch*>& fresh, const std::vector<Patch>& live, double d, std::uint64_t seed) {
  PointIndex centres;
  std::vector<const Patch*> owner;
  for (const Patch& p : live) centres.add(p.centre.point.position), owner.push_back(&p);
  std::vector<int> near;
  for (Patch* p : fresh) {
    centres.within(p->centre.point.position, kNeighbourSpan * d, near);
    std::vector<Vec2> taken;
    for (int i : near) {
      if (owner[i]->centre.normal.dot(p->centre.normal) > 0.0) taken.push_back(owner[i]->anchor);
    }
    double best = -1.0;
    for (int k = 0; k < kAnchorDraws && best < kAnchorSeparation; ++k) {
      const std::uint64_t draw = 2 * static_cast<std::uint64_t>(k);
      const Vec2 anchor(uniform(seed, Stream::PatchAnchor, p->id, draw),
                        uniform(seed, Stream::PatchAnchor, p->id, draw + 1));
      double nearest = 2.0;  // farther than any two anchors
      for (const Vec2& a : taken) nearest = std::min(nearest, anchor_distance(anchor, a));
      if (nearest > best) best = nearest, p->anchor = anchor;
    }
    centres.add(p->centre.point.position), owner.push_back(p);
  }
}

}  // namespace fluidtex
