#include "fluidtex/tracking/patch_builder.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include <Eigen/Geometry>  // Rotation2D

#include "fluidtex/geometry/disk_clip.h"
#include "fluidtex/geometry/disk_region.h"
#include "fluidtex/geometry/parameterization.h"
#include "fluidtex/tracking/patch_locator.h"
#include "fluidtex/util/random.h"

namespace fluidtex {

std::vector<int> select_patch_faces(const SurfaceIndex& surface, const SurfaceSample& centre, double select_radius,
                                    double patch_vertex_angle) {
  const FrameMesh& mesh = surface.mesh();
  const Vec3 c = centre.point.position;
  const Vec3 n = centre.normal;
  const double r2 = select_radius * select_radius;
  DiskRegionOptions region;
  region.accept = [&](int f) {
    // A triangle reaching into the selection ball counts (any corner or its
    // centroid inside): on meshes whose edges are a sizeable fraction of d, a
    // test on all corners would leave ragged, shrunken patches and gaps
    // between them.
    const Tri& t = mesh.triangles[f];
    const Vec3 centroid = (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
    bool reaches = (centroid - c).squaredNorm() <= r2;
    for (int v : t) reaches = reaches || (mesh.positions[v] - c).squaredNorm() <= r2;
    return reaches && surface.face_normals()[f].dot(n) > patch_vertex_angle;  // the plane test with pva
  };
  region.priority = [&](int f) {
    const Tri& t = mesh.triangles[f];
    return ((mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0 - c).squaredNorm();
  };
  // The disk's own triangle always belongs to its patch.
  return grow_disk_region(surface, centre.point.face, region);
}

namespace {

/// uv of the point of the patch nearest to `p` (through the nearest triangle).
Vec2 uv_at(const Patch& patch, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  Vec2 uv = Vec2::Zero();
  for (const Tri& t : patch.triangles) {
    const Vec3& a = patch.positions[t[0]];
    const Vec3& b = patch.positions[t[1]];
    const Vec3& c = patch.positions[t[2]];
    const Vec3 n = (b - a).cross(c - a);
    const double n2 = n.squaredNorm();
    if (!(n2 > 0.0)) continue;
    const Vec3 q = p - n * (n.dot(p - a) / n2);  // onto the triangle's plane
    const Vec3 w = barycentric(q, a, b, c);      // clamped into the triangle
    const Vec3 on = w[0] * a + w[1] * b + w[2] * c;
    const double d2 = (on - p).squaredNorm();
    if (d2 < best) {
      best = d2;
      uv = interpolate(patch.uvs, t, w);
    }
  }
  return uv;
}

/// The surface of a new patch: the faces select_patch_faces takes, copied,
/// cut to the selection cube and remeshed to `edge_length`; nullopt with
/// the reason in `why`.
std::optional<DiskMesh> patch_surface(const SurfaceIndex& surface, const SurfaceSample& centre,
                                      const TrackingOptions& options, double edge_length, const char*& why) {
  const double select_radius = (1.0 + options.selection_margin) * options.d();
  const std::vector<int> faces = select_patch_faces(surface, centre, select_radius, options.patch_vertex_angle);
  if (faces.empty()) {
    why = "empty selection";
    return std::nullopt;
  }
  DiskMesh copy = extract_faces(surface.mesh(), faces);  // a topological disk
  // Work bounded by the disk: the triangles that reach into the selection
  // ball end within it and one edge beyond; where the input's triangles are
  // large against d, they cover many times the ball, and the patch's
  // vertices (remeshed at a fraction of d) would grow with the square of
  // the triangles' size. A selection over kMaxSelectionArea balls is cut to
  // the cube of kSelectionCube balls' radius, whose section of a surface is
  // at most 7 balls.
  double area = 0.0;
  for (const Tri& t : copy.triangles) area += triangle_area(copy.positions, t);
  if (area > kMaxSelectionArea * M_PI * select_radius * select_radius)
    clip_disk_to_cube(copy, centre.point.position, kSelectionCube * select_radius);
  // Departure from the paper, which keeps the simulation's own triangles:
  // the copy is remeshed to well-shaped triangles of a set size (vertices
  // stay on the surface). Reconstructed surfaces are full of slivers whose
  // shape is noise, which the distortion metric reads as large distortion,
  // and their resolution varies; a remeshed patch follows the flow with a
  // fixed, sufficient number of vertices.
  if (edge_length > 0.0 && !remesh_disk(copy, edge_length)) {
    why = "selection is not manifold";
    return std::nullopt;
  }
  return copy;
}

}  // namespace

std::optional<Patch> build_patch(const SurfaceIndex& surface, const SurfaceSample& centre,
                                 const TrackingOptions& options, std::uint32_t id, std::uint64_t seed, int frame,
                                 double edge_length, std::string* failure) {
  auto fail = [&](const char* why) -> std::optional<Patch> {
    if (failure) *failure = why;
    return std::nullopt;
  };
  const char* cut = nullptr;
  const std::optional<DiskMesh> copy = patch_surface(surface, centre, options, edge_length, cut);
  if (!copy) return fail(cut);

  Patch patch;
  patch.id = id;
  patch.created_frame = frame;
  patch.centre = centre;
  patch.triangles = copy->triangles;
  for (const Vec3& p : copy->positions) {
    const SurfacePoint s = surface.closest_point(p);
    patch.positions.push_back(s.position);
    patch.projections.push_back(s);
  }
  if (patch.triangles.empty()) return fail("empty selection");
  std::string why;
  if (!flatten_lscm(*copy, patch.uvs, &why)) {
    if (failure) *failure = why;
    return std::nullopt;
  }
  const Vec2 uv_centre = uv_at(patch, centre.point.position);
  for (Vec2& uv : patch.uvs) uv -= uv_centre;

  // Drop triangles LSCM folded over (rare, on very curved selections).
  std::vector<Tri> kept;
  for (const Tri& t : patch.triangles) {
    if (signed_area(patch.uvs[t[0]], patch.uvs[t[1]], patch.uvs[t[2]]) > 0.0) kept.push_back(t);
  }
  if (kept.empty()) return fail("parameterisation folded over");
  const bool folded = kept.size() != patch.triangles.size();
  patch.triangles = std::move(kept);

  patch.rest.reserve(patch.triangles.size());
  for (const Tri& t : patch.triangles) {
    patch.rest.push_back(rest_shape(patch.positions[t[0]], patch.positions[t[1]], patch.positions[t[2]]));
  }
  patch.quality.assign(patch.positions.size(), 1.0f);
  patch.weight.assign(patch.positions.size(), 0.0f);
  if (folded) {
    remove_vertices(patch, std::vector<std::uint8_t>(patch.positions.size(), 1), surface);  // drops unused vertices
  } else {
    update_border(patch, surface);
  }
  patch.anchor = Vec2(uniform(seed, Stream::PatchAnchor, id, 0), uniform(seed, Stream::PatchAnchor, id, 1));
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) patch.disk_weight += seen_weight(patch, t, options.d());
  return patch;
}

namespace {

/// What `old` showed at `fresh`'s vertices: per vertex, Q_V (as its weight
/// shows it, 0 on its border) interpolated through the triangle of `old` the
/// vertex projects onto, 0 where none does; and, where both show their
/// texture, the pairs (uv of `fresh`, uv of `old`), each weighted by K_S's
/// radial term of both times that quality.
struct Matching {
  std::vector<float> shown;  ///< per vertex of `fresh`
  std::vector<Vec2> from, to;
  std::vector<double> weight;
};

Matching match_patches(const Patch& old, const Patch& fresh, const SurfaceIndex& surface,
                       const TrackingOptions& options) {
  const double d = options.d();
  std::vector<double> quality(old.num_vertices()), radial(old.num_vertices());
  for (std::size_t v = 0; v < quality.size(); ++v) {
    quality[v] = old.border[v] ? 0.0 : std::max(0.0, shown_quality(old, v));
    radial[v] = std::max(0.0, 1.0 - old.uvs[v].norm() / d);
  }
  std::vector<TrianglePrism> prisms;
  std::vector<TriangleProjection> projections;
  prisms.reserve(old.triangles.size());
  projections.reserve(old.triangles.size());
  for (const Tri& t : old.triangles) {
    prisms.emplace_back(old, t, options.mpt());
    projections.emplace_back(old, t, options.mpt());
  }
  Matching m;
  m.shown.assign(fresh.num_vertices(), 0.0f);
  for (std::size_t v = 0; v < fresh.num_vertices(); ++v) {
    const Vec3& q = fresh.positions[v];
    const Vec3 n = surface.normal_at(fresh.projections[v]);
    double best = std::numeric_limits<double>::infinity();
    Vec2 uv = Vec2::Zero();
    double seen = 0.0;
    for (std::size_t k = 0; k < old.triangles.size(); ++k) {
      const Tri& t = old.triangles[k];
      Vec3 l;
      double dist2 = 0.0;
      if (!prisms[k].may_cover(q)) continue;
      if (!projections[k].project(q, n, l, dist2) || !(dist2 < best)) continue;
      best = dist2;
      uv = interpolate(old.uvs, t, l);
      m.shown[v] = static_cast<float>(l[0] * quality[t[0]] + l[1] * quality[t[1]] + l[2] * quality[t[2]]);
      seen = l[0] * radial[t[0]] + l[1] * radial[t[1]] + l[2] * radial[t[2]];
    }
    const double w = m.shown[v] * seen * std::max(0.0, 1.0 - fresh.uvs[v].norm() / d);
    if (!(w > 0.0)) continue;
    m.from.push_back(fresh.uvs[v]);
    m.to.push_back(uv);
    m.weight.push_back(w);
  }
  return m;
}

}  // namespace

std::optional<Patch> recut_patch(const Patch& old, const SurfaceIndex& surface, const TrackingOptions& options,
                                 std::uint64_t seed, int frame, double edge_length) {
  std::optional<Patch> fresh = build_patch(surface, old.centre, options, old.id, seed, frame, edge_length);
  if (!fresh) return std::nullopt;
  Matching pairs = match_patches(old, *fresh, surface, options);
  if (pairs.weight.size() < 3) return std::nullopt;
  // The rotation R and shift t that best carry the new uv onto the old
  // (weighted least squares, no scaling: the new patch is undistorted, and
  // its uv stay metric with the centre at the origin).
  double sum = 0.0;
  Vec2 from_mean = Vec2::Zero(), to_mean = Vec2::Zero();
  for (std::size_t k = 0; k < pairs.weight.size(); ++k) {
    sum += pairs.weight[k];
    from_mean += pairs.weight[k] * pairs.from[k];
    to_mean += pairs.weight[k] * pairs.to[k];
  }
  from_mean /= sum, to_mean /= sum;
  double dot = 0.0, cross = 0.0;
  for (std::size_t k = 0; k < pairs.weight.size(); ++k) {
    const Vec2 a = pairs.from[k] - from_mean, b = pairs.to[k] - to_mean;
    dot += pairs.weight[k] * a.dot(b);
    cross += pairs.weight[k] * (a.x() * b.y() - a.y() * b.x());
  }
  if (!(std::abs(dot) + std::abs(cross) > 0.0)) return std::nullopt;  // every pair at one point
  const Eigen::Rotation2Dd turn(std::atan2(cross, dot));
  for (Vec2& uv : fresh->uvs) uv = turn * uv;  // the rest shapes do not depend on it
  // Old texture at a point: offset + uv_old; new: offset' + R·uv_new, and
  // uv_old ≈ R·uv_new + t.
  fresh->texture_offset = old.texture_offset + (to_mean - turn * from_mean);
  // Each vertex shows at first what the old patch showed there; where that
  // was crushed or torn (little shown), the new texture fades in.
  fresh->recovery = std::move(pairs.shown);
  fresh->anchor = old.anchor;
  fresh->state = old.state;
  fresh->kt = old.kt;
  fresh->created_frame = old.created_frame;
  fresh->recut_frame = frame;
  fresh->close_frames = old.close_frames;
  fresh->sunk = old.sunk;
  fresh->density = old.density;
  fresh->motion = old.motion;
  return fresh;
}

}  // namespace fluidtex
