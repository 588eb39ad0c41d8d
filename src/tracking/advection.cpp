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

}  // namespace fluidtex
