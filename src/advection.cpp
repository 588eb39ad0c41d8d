#include "fluidtex/advection.h"

#include <algorithm>
#include <cmath>

#include "fluidtex/error.h"

namespace fluidtex {

const char* to_string(Advection a) { return a == Advection::Euler ? "euler" : "heun"; }

Advection advection_from_string(const std::string& s) {
  if (s == "euler") return Advection::Euler;
  if (s == "heun") return Advection::Heun;
  throw InputError("", "--advection must be euler or heun (got '" + s + "')");
}

SurfacePoint advect_point(const SurfacePoint& from, const SurfaceIndex& previous, const SurfaceIndex& next,
                          double dt, Advection scheme) {
  const Vec3 v0 = previous.velocity_at(from);
  const Vec3 guess = from.position + v0 * dt;
  SurfacePoint to = next.closest_point(guess);
  if (scheme == Advection::Heun && to.valid()) {
    const Vec3 v1 = next.velocity_at(to);
    const Vec3 target = from.position + 0.5 * (v0 + v1) * dt;
    to = next.closest_point(target);
    to.distance = (to.position - target).norm();
  }
  return to;
}

namespace {

/// A point whose closest surface point is on the rim of an open surface and
/// that lies beyond it in the tangent plane has left the fluid region (an
/// outflow boundary of the 2D scenes): remove it rather than squash it onto
/// the rim, which would only distort the patch. `p.distance` is the offset.
bool left_through_rim(const SurfacePoint& p, const SurfaceIndex& surface, double max_projection) {
  return p.distance > 0.1 * max_projection && surface.on_boundary(p);
}

}  // namespace

AdvectResult advect_patch(Patch& patch, const SurfaceIndex& previous, const SurfaceIndex& next, double dt,
                          double max_projection, double radius, Advection scheme) {
  const SurfacePoint centre = advect_point(patch.center.point, previous, next, dt, scheme);
  if (!centre.valid() || centre.distance > max_projection) return AdvectResult::Lost;
  patch.center.point = centre;
  patch.center.normal = next.normal_at(centre);

  std::vector<std::uint8_t> keep(patch.positions.size(), 1);
  bool removed = false, damaged = false;
  for (std::size_t v = 0; v < patch.positions.size(); ++v) {
    const SurfacePoint p = advect_point(patch.projections[v], previous, next, dt, scheme);
    if (!p.valid() || p.distance > max_projection || left_through_rim(p, next, max_projection)) {
      keep[v] = 0;
      removed = true;
      damaged = damaged || patch.uvs[v].norm() < radius;
      continue;
    }
    patch.projections[v] = p;
    patch.positions[v] = p.position;
  }
  if (removed) remove_vertices(patch, keep, next);
  else update_border(patch, next);
  if (patch.triangles.empty()) return AdvectResult::Lost;
  return damaged ? AdvectResult::Damaged : AdvectResult::Kept;
}

bool update_distortion(Patch& patch, const SurfaceIndex& surface, const TrackingOptions& options) {
  // Only where the patch contributes (|uv| < d, K_S > 0) can its distortion
  // show; the margin out to (1 + β)d only keeps the border away from it.
  auto inside = [&](int v) { return patch.uvs[v].norm() < options.radius; };
  // Margin triangles (no corner inside the disk) stretched beyond δmax are
  // cut off: they carry almost no weight, and unbounded they would grow
  // without limit in diverging flows.
  std::vector<std::uint8_t> keep(patch.triangles.size(), 1);
  bool cut = false;
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    const Tri& tri = patch.triangles[t];
    if (inside(tri[0]) || inside(tri[1]) || inside(tri[2])) continue;
    const double d = triangle_distortion(patch.rest[t], patch.positions[tri[0]], patch.positions[tri[1]],
                                         patch.positions[tri[2]]);
    if (d > options.max_distortion) keep[t] = 0, cut = true;
  }
  if (cut) remove_triangles(patch, keep, surface);
  const std::size_t nv = patch.positions.size();
  std::vector<double> sum(nv, 0.0);
  std::vector<int> count(nv, 0);
  std::vector<double> weight(nv, 0.0);
  bool distorted = false;
  patch.max_distortion = 1.0;
  const auto& component = surface.face_component();
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    const Tri& tri = patch.triangles[t];
    const bool visible = inside(tri[0]) || inside(tri[1]) || inside(tri[2]);
    const Vec3& q0 = patch.positions[tri[0]];
    const Vec3& q1 = patch.positions[tri[1]];
    const Vec3& q2 = patch.positions[tri[2]];
    const double d = triangle_distortion(patch.rest[t], q0, q1, q2);
    if (visible) patch.max_distortion = std::max(patch.max_distortion, d);
    const double q = triangle_quality(d, options.max_distortion);
    // Area-weighted mean (rest area): reconstructed surfaces are full of
    // slivers whose shape is noise, and a plain mean lets one of them decide.
    const RestTriangle& r = patch.rest[t];
    const double area = 0.5 * std::abs((r[1] - r[0]).x() * (r[2] - r[0]).y() - (r[1] - r[0]).y() * (r[2] - r[0]).x());
    for (int v : tri) {
      sum[v] += q * area;
      weight[v] += area;
      ++count[v];
    }
    // Flipped: the triangle's normal turned against the surface under it.
    const Vec3 n = (q1 - q0).cross(q2 - q0);
    Vec3 surface_n = Vec3::Zero();
    for (int v : tri) surface_n += surface.normal_at(patch.projections[v]);
    if (visible && n.dot(surface_n) < 0.0) distorted = true;
    // Stretched across two disconnected pieces of the surface.
    const int c0 = component[patch.projections[tri[0]].face];
    if (visible && (component[patch.projections[tri[1]].face] != c0 || component[patch.projections[tri[2]].face] != c0)) {
      distorted = true;
    }
  }
  patch.quality.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    patch.quality[v] = weight[v] > 0.0 ? static_cast<float>(sum[v] / weight[v]) : 0.0f;
    if (count[v] && inside(static_cast<int>(v)) && patch.quality[v] < options.min_vertex_quality) distorted = true;
  }
  return distorted;
}

void update_weights(Patch& patch, const TrackingOptions& options) {
  const std::size_t nv = patch.positions.size();
  patch.weight.resize(nv);
  const double d_uv = options.radius;
  const double reach = (1.0 + options.selection_margin) * options.radius;
  for (std::size_t v = 0; v < nv; ++v) {
    const double r = patch.uvs[v].norm();  // p_uv is the origin
    const double radial = std::max(0.0, 1.0 - r / d_uv) + kCoverageTail * std::max(0.0, 1.0 - r / reach);
    const double quality = std::max<double>(patch.quality[v], kCoverageTail);
    const double ks = radial * options.uv_scale * (patch.border[v] ? 0.0 : 1.0) * quality;  // Eq. 4
    patch.weight[v] = static_cast<float>(ks * patch.kt);                                              // Eq. 2
  }
}

}  // namespace fluidtex
