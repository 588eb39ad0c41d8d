#include "fluidtex/tracking/patch_distortion.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "fluidtex/geometry/distortion.h"
#include "fluidtex/util/error.h"

namespace fluidtex {

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

}  // namespace fluidtex
