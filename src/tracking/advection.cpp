#include "fluidtex/tracking/advection.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "fluidtex/util/error.h"

namespace fluidtex {

Vec3 advect_target(const SurfacePoint& from, const SurfaceIndex& previous, const SurfaceIndex& next, double dt,
                   Advection scheme) {
  const Vec3 v0 = previous.velocity_at(from);
  Vec3 guess = from.position + v0 * dt;
  if (scheme != Advection::Heun) return guess;
  const SurfacePoint at = next.closest_point(guess);
  if (!at.valid()) return guess;
  return from.position + 0.5 * (v0 + next.velocity_at(at)) * dt;
}

namespace {

using Basis = Eigen::Matrix<double, SmoothMap::kTerms, 1>;

/// Monomials of u/d, v/d by degree: 1 | u v | u² uv v² | u³ u²v uv² v³.
Basis polynomial_basis(const Vec2& uv, double scale) {
  const double u = uv.x() / scale, v = uv.y() / scale;
  Basis b;
  b << 1.0, u, v, u * u, u * v, v * v, u * u * u, u * u * v, u * v * v, v * v * v;
  return b;
}

}  // namespace

Vec3 SmoothMap::operator()(const Vec2& uv) const { return coefficients.transpose() * polynomial_basis(uv, scale); }

bool fit_smooth_map(const Patch& patch, const std::vector<Vec3>& targets, const TrackingOptions& options,
                    SmoothMap& map) {
  const double scale = options.d();
  const std::size_t nv = patch.uvs.size();
  std::vector<double> area(nv, 0.0);
  for (const Tri& t : patch.triangles) {
    const double a = triangle_area(patch.uvs, t) / 3.0;  // a third to each corner
    for (int v : t) area[v] += a;
  }
  // Normal equations of the weighted fit; lower degrees come first, so the
  // leading 6×6 and 3×3 blocks are the quadratic and the affine fits'.
  constexpr int n = SmoothMap::kTerms;
  Eigen::Matrix<double, n, n> ata = Eigen::Matrix<double, n, n>::Zero();
  Eigen::Matrix<double, n, 3> atb = Eigen::Matrix<double, n, 3>::Zero();
  for (std::size_t v = 0; v < nv; ++v) {
    const double w = area[v] * radial_weight(patch.uvs[v].norm(), options);
    if (!(w > 0.0)) continue;
    const Basis b = polynomial_basis(patch.uvs[v], scale);
    ata.noalias() += w * b * b.transpose();
    atb.noalias() += w * b * targets[v].transpose();
  }
  map = SmoothMap{};
  map.scale = scale;
  // Accept a fit only when its normal matrix is well conditioned (the uv
  // spread is a fair share of d in every direction the terms need).
  auto solve = [&](int terms) {
    const Eigen::MatrixXd m = ata.topLeftCorner(terms, terms);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(m);
    if (eig.info() != Eigen::Success || !(eig.eigenvalues()(0) > 1e-6 * eig.eigenvalues()(terms - 1))) return false;
    map.coefficients.topRows(terms) = m.ldlt().solve(atb.topRows(terms));
    return map.coefficients.allFinite();
  };
  if (solve(n)) return true;
  map.coefficients.setZero();
  if (solve(6)) return true;
  map.coefficients.setZero();
  return solve(3);
}

namespace {

/// A point whose closest surface point is on the rim of an open surface and
/// that lies beyond it in the tangent plane has left the fluid region (an
/// outflow boundary of the 2D scenes): remove it rather than squash it onto
/// the rim, which would only distort the patch. `p.distance` is the offset.
bool left_through_rim(const SurfacePoint& p, const SurfaceIndex& surface, double max_projection) {
  return p.distance > 0.1 * max_projection && surface.on_boundary(p);
}

/// Where a vertex on the previous frame's rim (`from`), carried to `target`
/// and projected inside the next surface at `to`, goes when it belongs on
/// the next frame's rim: the rim moved with the liquid (the outline of the
/// 2D scenes as it spreads or contracts) when the vertex lands closer to the
/// new rim than its old place lies. A rim the liquid enters through stays
/// where it was, and the liquid moves away from it. Velocities sampled at the
/// frame's instant lag an accelerating rim by ½·a·dt² a frame; without this
/// the lag would accumulate and bare a sliver of faces along the rim, which
/// the coverage net would fill with new disks every frame. Returns the rim
/// point, its distance measured from `target`; invalid when the vertex does
/// not belong on the rim.
SurfacePoint carried_rim_point(const SurfacePoint& from, const SurfacePoint& to, const Vec3& target,
                               const SurfaceIndex& previous, const SurfaceIndex& next, double max_projection) {
  if (!previous.on_boundary(from) || next.on_boundary(to)) return {};
  SurfacePoint rim = next.closest_rim_point(to.position, max_projection);
  if (!rim.valid()) return {};
  const SurfacePoint old_rim = next.closest_rim_point(from.position, rim.distance);
  if (old_rim.valid() && !(old_rim.distance > rim.distance)) return {};
  rim.distance = (rim.position - target).norm();
  return rim;
}

}  // namespace

double projection_tolerance(const SurfacePoint& from, const Vec3& normal, const Vec3& target,
                            const TrackingOptions& options) {
  return options.mpt() + options.projection_slack * std::abs((target - from.position).dot(normal));
}

namespace {

/// Where a patch's vertices and centre are carried before projection: each
/// vertex by its own velocity, or with PatchMotion::Smooth by the cubic map
/// fitted to those (`raw` then keeps the vertices' own targets).
struct PatchTargets {
  std::vector<Vec3> vertex, raw;
  Vec3 centre;
};

PatchTargets patch_targets(const Patch& patch, const SurfaceIndex& previous, const SurfaceIndex& next, double dt,
                           const TrackingOptions& options, Advection scheme, PatchMotion motion) {
  const std::size_t nv = patch.positions.size();
  PatchTargets t;
  t.vertex.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) t.vertex[v] = advect_target(patch.projections[v], previous, next, dt, scheme);
  SmoothMap map;
  if (motion == PatchMotion::Smooth && fit_smooth_map(patch, t.vertex, options, map)) {
    t.raw = t.vertex;
    for (std::size_t v = 0; v < nv; ++v) t.vertex[v] = map(patch.uvs[v]);
    t.centre = map(Vec2::Zero());
  } else {
    t.centre = advect_target(patch.centre.point, previous, next, dt, scheme);
  }
  return t;
}

/// The closest point of `next` to `target`, with its distance from it.
SurfacePoint project_onto(const SurfaceIndex& next, const Vec3& target) {
  SurfacePoint to = next.closest_point(target);
  to.distance = (to.position - target).norm();
  return to;
}

/// Which of a patch's vertices stay after projection.
struct VertexLandings {
  std::vector<std::uint8_t> keep;
  std::size_t kept = 0;
  bool damaged = false;  ///< a vertex inside the disk was removed
};

/// Projects every vertex of `patch` from its target onto `next` (moving the
/// vertices that stay); a vertex that lands beyond the projection tolerance
/// or leaves through an open rim is to be removed.
VertexLandings carry_vertices(Patch& patch, const PatchTargets& targets, const SurfaceIndex& previous,
                              const SurfaceIndex& next, const TrackingOptions& options) {
  const double max_projection = options.mpt();
  const std::size_t nv = patch.positions.size();
  VertexLandings out{std::vector<std::uint8_t>(nv, 1), nv, false};
  for (std::size_t v = 0; v < nv; ++v) {
    Vec3 target = targets.vertex[v];
    SurfacePoint p = project_onto(next, target);
    // Along an open rim (the 2D scenes' outflow boundaries) a vertex follows
    // its own motion: the map, fitted to a flow along a rim drawn with
    // chords, lands a hair inside or outside it, which would turn rim edges
    // into patch borders or remove their vertices.
    if (!targets.raw.empty() && p.valid() && next.on_boundary(p, max_projection))
      p = project_onto(next, target = targets.raw[v]);
    const SurfacePoint rim =
        p.valid() ? carried_rim_point(patch.projections[v], p, target, previous, next, max_projection) : SurfacePoint{};
    const bool on_rim = rim.valid();
    if (on_rim) p = rim;
    // Most points land within mpt; only the others need the normal's share.
    if (!p.valid() ||
        (p.distance > max_projection &&
         p.distance >
             projection_tolerance(patch.projections[v], previous.normal_at(patch.projections[v]), target, options)) ||
        (!on_rim && left_through_rim(p, next, max_projection))) {
      out.keep[v] = 0;
      --out.kept;
      out.damaged = out.damaged || patch.uvs[v].norm() < options.d();
      continue;
    }
    patch.projections[v] = p;
    patch.positions[v] = p.position;
  }
  return out;
}

}  // namespace

AdvectResult advect_patch(Patch& patch, const SurfaceIndex& previous, const SurfaceIndex& next, double dt,
                          const TrackingOptions& options, Advection scheme, PatchMotion motion) {
  const double max_projection = options.mpt(), radius = options.d();
  const std::size_t nv = patch.positions.size();
  const PatchTargets targets = patch_targets(patch, previous, next, dt, options, scheme, motion);
  const Vec3& centre_target = targets.centre;
  SurfacePoint centre = project_onto(next, centre_target);
  if (!centre.valid()) return AdvectResult::CentreLost;
  const SurfacePoint centre_rim =
      carried_rim_point(patch.centre.point, centre, centre_target, previous, next, max_projection);
  const bool centre_on_rim = centre_rim.valid();
  if (centre_on_rim) centre = centre_rim;
  // A centre that left through an open rim (an outflow) has left the
  // liquid, however little it moved past the rim in a frame: it stays on the
  // rim while the patch fades out (LeftThroughRim). Taken back onto the rim
  // as a near miss, it stayed there for good while the liquid it stood for
  // flowed on, and disks piled up along the outflow wherever the liquid
  // moves less than mpt a frame. A centre that misses the surface elsewhere
  // is mostly a near miss (an overshoot of a fast sheet, noisy velocities)
  // where the patch still lies on the liquid: with recut, the patch's
  // vertices decide (below).
  const bool centre_left = !centre_on_rim && left_through_rim(centre, next, max_projection);
  const bool centre_missed =
      !centre_left &&
      centre.distance > projection_tolerance(patch.centre.point, patch.centre.normal, centre_target, options);
  if (centre_missed && options.distorted != Distorted::Recut) return AdvectResult::CentreLost;
  // The motion (in d a frame) sets a fade's pace under --fading flow: for a
  // centre that left through an outflow, the liquid's own motion, so that
  // the patch fades in about the frames its disk takes to flow out.
  patch.motion = ((centre_left ? centre_target : centre.position) - patch.centre.point.position).norm() / radius;
  patch.centre.point = centre;
  patch.centre.normal = next.normal_at(centre);

  const VertexLandings landed = carry_vertices(patch, targets, previous, next, options);
  if (centre_missed && !(2 * landed.kept > nv)) return AdvectResult::CentreLost;
  if (landed.kept < nv)
    remove_vertices(patch, landed.keep, next);
  else
    update_border(patch, next);
  if (patch.triangles.empty()) return AdvectResult::Emptied;
  if (centre_left) return AdvectResult::LeftThroughRim;
  if (centre_missed) return AdvectResult::CentreMoved;
  return landed.damaged ? AdvectResult::Damaged : AdvectResult::Kept;
}

namespace {

/// Whether vertex v is inside the disk (|uv| < d): only there does a patch
/// contribute (K_S > 0) and its distortion show; the margin out to (1 + β)d
/// only keeps the border away from it.
bool inside_disk(const Patch& patch, int v, const TrackingOptions& options) {
  return patch.uvs[v].norm() < options.d();
}
bool touches_disk(const Patch& patch, const Tri& tri, const TrackingOptions& options) {
  return inside_disk(patch, tri[0], options) || inside_disk(patch, tri[1], options) ||
         inside_disk(patch, tri[2], options);
}

/// Each triangle's Sorkine distortion, after cutting off the margin
/// triangles (no corner inside the disk) stretched beyond δmax: they carry
/// almost no weight, and unbounded they would grow without limit in
/// diverging flows.
std::vector<double> cut_stretched_margin(Patch& patch, const SurfaceIndex& surface, const TrackingOptions& options) {
  std::vector<double> distortion(patch.triangles.size());
  std::vector<std::uint8_t> keep(patch.triangles.size(), 1);
  bool cut = false;
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    const Tri& tri = patch.triangles[t];
    distortion[t] =
        triangle_distortion(patch.rest[t], patch.positions[tri[0]], patch.positions[tri[1]], patch.positions[tri[2]]);
    if (touches_disk(patch, tri, options)) continue;
    if (distortion[t] > options.max_distortion) keep[t] = 0, cut = true;
  }
  if (cut) {
    remove_triangles(patch, keep, surface);  // keeps the order of the kept triangles
    std::size_t next = 0;
    for (std::size_t t = 0; t < keep.size(); ++t) {
      if (keep[t]) distortion[next++] = distortion[t];
    }
    distortion.resize(next);
  }
  return distortion;
}

/// What the triangles of a patch say about it: per-vertex quality sums, the
/// per-vertex rule's flags, and at patch scale what the disk still shows (the
/// seen weight of its intact triangles times their mean Q_T over the disk's
/// current area; flipped and split triangles show nothing) and what each rule
/// takes away.
struct DistortionTally {
  std::vector<double> sum, weight;
  std::vector<int> count;
  bool flipped = false, split = false;
  double shown = 0.0, present = 0.0, loss_flipped = 0.0, loss_split = 0.0, loss_stretch = 0.0;
};

DistortionTally tally_triangles(Patch& patch, const SurfaceIndex& surface, const std::vector<double>& distortion,
                                const TrackingOptions& options) {
  const std::size_t nv = patch.positions.size();
  // The surface normal under each vertex, once (a vertex has several triangles).
  std::vector<Vec3> surface_normal(nv);
  for (std::size_t v = 0; v < nv; ++v) surface_normal[v] = surface.normal_at(patch.projections[v]);
  DistortionTally out;
  out.sum.assign(nv, 0.0), out.weight.assign(nv, 0.0), out.count.assign(nv, 0);
  patch.max_distortion = 1.0;
  const auto& component = surface.face_component();
  // The disk's quality is the mean Q_T over what it shows now: weighted by
  // the radial term of K_S times each triangle's current area, over the
  // triangles neither flipped nor split (those count their seen weight as
  // lost). A triangle the flow has crushed into a sliver shows almost
  // nothing, and its vertices' Q_V already take its weight away in Eq. 4.
  double intact = 0.0, now_weight = 0.0, now_quality = 0.0;
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    const Tri& tri = patch.triangles[t];
    const bool visible = touches_disk(patch, tri, options);
    const double d = distortion[t];
    if (visible) patch.max_distortion = std::max(patch.max_distortion, d);
    const double q = triangle_quality(d, options.max_distortion);
    // Area-weighted mean (rest area): reconstructed surfaces are full of
    // slivers whose shape is noise, and a plain mean lets one of them decide.
    const RestTriangle& r = patch.rest[t];
    const double area = triangle_area(r[0], r[1], r[2]);
    for (int v : tri) {
      out.sum[v] += q * area;
      out.weight[v] += area;
      ++out.count[v];
    }
    // Flipped: the triangle's normal turned against the surface under it.
    const Vec3& q0 = patch.positions[tri[0]];
    const Vec3 n = (patch.positions[tri[1]] - q0).cross(patch.positions[tri[2]] - q0);
    Vec3 surface_n = Vec3::Zero();
    for (int v : tri) surface_n += surface_normal[v];
    const bool tri_flipped = n.dot(surface_n) < 0.0;
    // Stretched across two disconnected pieces of the surface.
    const int c0 = component[patch.projections[tri[0]].face];
    const bool tri_split =
        component[patch.projections[tri[1]].face] != c0 || component[patch.projections[tri[2]].face] != c0;
    if (visible) out.flipped = out.flipped || tri_flipped, out.split = out.split || tri_split;
    const double w = seen_weight(patch, t, options.d());
    out.present += w;
    if (tri_split)
      out.loss_split += w;
    else if (tri_flipped)
      out.loss_flipped += w;
    else {
      intact += w;
      const double now = area > 0.0 ? w * (0.5 * n.norm()) / area : 0.0;  // radial term × current area
      now_weight += now, now_quality += now * q;
    }
  }
  const double mean_q = now_weight > 0.0 ? now_quality / now_weight : 0.0;
  out.shown = intact * mean_q, out.loss_stretch = intact * (1.0 - mean_q);
  return out;
}

}  // namespace

RetireCause update_distortion(Patch& patch, const SurfaceIndex& surface, const TrackingOptions& options) {
  const std::vector<double> distortion = cut_stretched_margin(patch, surface, options);
  const DistortionTally tally = tally_triangles(patch, surface, distortion, options);
  const std::size_t nv = patch.positions.size();
  bool poor = false;
  patch.quality.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    patch.quality[v] = tally.weight[v] > 0.0 ? static_cast<float>(tally.sum[v] / tally.weight[v]) : 0.0f;
    if (options.distortion_test == DistortionTest::Vertex && tally.count[v] &&
        inside_disk(patch, static_cast<int>(v), options) && patch.quality[v] < options.min_vertex_quality) {
      poor = true;
    }
  }
  if (options.distortion_test == DistortionTest::Patch) {
    // Lost triangles (vertices removed past mpt) show nothing either.
    const double whole = std::max(patch.disk_weight, tally.present);
    if (!(whole > 0.0) || tally.shown >= options.min_vertex_quality * whole) return RetireCause::None;
    const double loss_lost = whole - tally.present;
    const double worst = std::max({loss_lost, tally.loss_split, tally.loss_flipped, tally.loss_stretch});
    if (worst == tally.loss_split) return RetireCause::Split;
    if (worst == tally.loss_flipped) return RetireCause::Flipped;
    return worst == loss_lost ? RetireCause::VerticesLost : RetireCause::Quality;
  }
  if (tally.split) return RetireCause::Split;
  if (tally.flipped) return RetireCause::Flipped;
  return poor ? RetireCause::Quality : RetireCause::None;
}

double tail_weight(double r, const TrackingOptions& options) {
  const double reach = (1.0 + options.selection_margin) * options.d();
  return kCoverageTail * std::max(0.0, 1.0 - r / reach);
}

double radial_weight(double r, const TrackingOptions& options) {
  return std::max(0.0, 1.0 - r / options.d()) + tail_weight(r, options);  // d_uv = d
}

float core_weight(const Patch& patch, std::size_t v, double radius, double uv_scale) {
  const double radial = std::max(0.0, 1.0 - patch.uvs[v].norm() / radius);  // d_uv = d, p_uv is the origin
  const double ks =
      radial * uv_scale * (patch.border[v] ? 0.0 : 1.0) * std::max(0.0, shown_quality(patch, v));  // Eq. 4
  return static_cast<float>(ks * patch.kt);                                                        // Eq. 2
}

void update_weights(Patch& patch, const TrackingOptions& options) {
  const std::size_t nv = patch.positions.size();
  patch.weight.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    const double quality = std::max(shown_quality(patch, v), kCoverageTail);
    const double r = patch.uvs[v].norm();  // p_uv is the origin
    // d_V = 0 on the border takes the disk's term (Eq. 4), not the tail.
    const double ks =
        (patch.border[v] ? tail_weight(r, options) : radial_weight(r, options)) * options.uv_scale * quality;
    patch.weight[v] = static_cast<float>(ks * patch.kt);  // Eq. 2
  }
}

}  // namespace fluidtex
