#include "fluidtex/patch_builder.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>

#include "fluidtex/disk_region.h"
#include "fluidtex/random.h"

namespace fluidtex {

std::vector<int> select_patch_faces(const SurfaceIndex& surface, const SurfaceSample& center,
                                    double select_radius, double patch_vertex_angle) {
  const FrameMesh& mesh = surface.mesh();
  const Vec3 c = center.point.position;
  const Vec3 n = center.normal;
  const double r2 = select_radius * select_radius;
  DiskRegionOptions region;
  region.accept = [&](int f) {
    for (int v : mesh.triangles[f]) {
      if ((mesh.positions[v] - c).squaredNorm() > r2) return false;
    }
    return surface.face_normals()[f].dot(n) > patch_vertex_angle;  // the plane test with pva
  };
  region.priority = [&](int f) {
    const Tri& t = mesh.triangles[f];
    return ((mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0 - c).squaredNorm();
  };
  // The disk's own triangle always belongs to its patch.
  return grow_disk_region(surface, center.point.face, region);
}

namespace {

using K = CGAL::Simple_cartesian<double>;
using SM = CGAL::Surface_mesh<K::Point_3>;
using VD = SM::Vertex_index;

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
    const Vec3 w = barycentric(q, a, b, c);     // clamped into the triangle
    const Vec3 on = w[0] * a + w[1] * b + w[2] * c;
    const double d2 = (on - p).squaredNorm();
    if (d2 < best) {
      best = d2;
      uv = w[0] * patch.uvs[t[0]] + w[1] * patch.uvs[t[1]] + w[2] * patch.uvs[t[2]];
    }
  }
  return uv;
}

}  // namespace

std::optional<Patch> build_patch(const SurfaceIndex& surface, const SurfaceSample& center,
                                 const TrackingOptions& options, std::uint32_t id, std::uint64_t seed,
                                 int frame, double edge_length, std::string* failure) {
  auto fail = [&](const char* why) -> std::optional<Patch> {
    if (failure) *failure = why;
    return std::nullopt;
  };
  const FrameMesh& mesh = surface.mesh();
  const std::vector<int> faces = select_patch_faces(
      surface, center, (1.0 + options.selection_margin) * options.radius, options.patch_vertex_angle);
  if (faces.empty()) return fail("empty selection");

  // Copy the selection into a CGAL Surface_mesh (a topological disk).
  SM sm;
  {
    std::unordered_map<int, VD> local;
    for (int f : faces) {
      const Tri& t = mesh.triangles[f];
      VD v[3];
      for (int k = 0; k < 3; ++k) {
        auto it = local.find(t[k]);
        if (it == local.end()) {
          const Vec3& p = mesh.positions[t[k]];
          it = local.emplace(t[k], sm.add_vertex(K::Point_3(p.x(), p.y(), p.z()))).first;
        }
        v[k] = it->second;
      }
      if (sm.add_face(v[0], v[1], v[2]) == SM::null_face()) return fail("selection is not manifold");
    }
  }
  // Remesh the copy to well-shaped triangles of a set size (CGAL isotropic
  // remeshing; vertices stay on the copied surface, border edges on the
  // border). Departure from the paper, which keeps the simulation's own
  // triangles: reconstructed surfaces are full of slivers whose shape is
  // noise, which the distortion metric reads as large distortion, and their
  // resolution varies; a remeshed patch follows the flow with a fixed,
  // sufficient number of vertices.
  if (edge_length > 0.0) {
    namespace PMP = CGAL::Polygon_mesh_processing;
    PMP::isotropic_remeshing(sm.faces(), edge_length, sm, CGAL::parameters::number_of_iterations(3));
    sm.collect_garbage();
  }

  Patch patch;
  patch.id = id;
  patch.created_frame = frame;
  patch.center = center;
  std::vector<VD> vds;
  {
    std::unordered_map<std::uint32_t, int> index;
    for (VD v : sm.vertices()) {
      index.emplace(static_cast<std::uint32_t>(v), static_cast<int>(vds.size()));
      vds.push_back(v);
      const K::Point_3& p = sm.point(v);
      const SurfacePoint s = surface.closest_point(Vec3(p.x(), p.y(), p.z()));
      patch.positions.push_back(s.position);
      patch.projections.push_back(s);
    }
    for (SM::Face_index f : sm.faces()) {
      Tri t{};
      int k = 0;
      for (VD v : CGAL::vertices_around_face(sm.halfedge(f), sm)) t[k++] = index.at(static_cast<std::uint32_t>(v));
      patch.triangles.push_back(t);
    }
  }
  if (patch.triangles.empty()) return fail("empty selection");

  // LSCM (Lévy et al. 2002), from a border halfedge.
  SM::Halfedge_index border = SM::null_halfedge();
  for (SM::Halfedge_index h : sm.halfedges()) {
    if (sm.is_border(h)) {
      border = h;
      break;
    }
  }
  if (border == SM::null_halfedge()) return fail("selection has no boundary");
  auto uvmap = sm.add_property_map<VD, K::Point_2>("v:uv").first;
  namespace SMP = CGAL::Surface_mesh_parameterization;
  if (SMP::parameterize(sm, SMP::LSCM_parameterizer_3<SM>(), border, uvmap) != SMP::OK) {
    return fail("LSCM solve failed");
  }
  patch.uvs.resize(vds.size());
  for (std::size_t v = 0; v < vds.size(); ++v) {
    const K::Point_2& uv = uvmap[vds[v]];
    patch.uvs[v] = Vec2(uv.x(), uv.y());
  }

  // Metric scale (uv area = 3D area), orientation, and centring on the disk.
  double area3 = 0.0, area_uv = 0.0;
  for (const Tri& t : patch.triangles) {
    area3 += 0.5 * (patch.positions[t[1]] - patch.positions[t[0]]).cross(patch.positions[t[2]] - patch.positions[t[0]]).norm();
    const Vec2 e1 = patch.uvs[t[1]] - patch.uvs[t[0]], e2 = patch.uvs[t[2]] - patch.uvs[t[0]];
    area_uv += 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
  }
  if (!(std::abs(area_uv) > 0.0) || !(area3 > 0.0) || !std::isfinite(area_uv)) return fail("degenerate parameterisation");
  const double scale = std::sqrt(area3 / std::abs(area_uv));
  const double mirror = area_uv < 0.0 ? -1.0 : 1.0;
  for (Vec2& uv : patch.uvs) uv = Vec2(mirror * uv.x(), uv.y()) * scale;
  const Vec2 uv_center = uv_at(patch, center.point.position);
  for (Vec2& uv : patch.uvs) uv -= uv_center;

  // Drop triangles LSCM folded over (rare, on very curved selections).
  std::vector<Tri> kept;
  for (const Tri& t : patch.triangles) {
    const Vec2 e1 = patch.uvs[t[1]] - patch.uvs[t[0]], e2 = patch.uvs[t[2]] - patch.uvs[t[0]];
    if (e1.x() * e2.y() - e1.y() * e2.x() > 0.0) kept.push_back(t);
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
  return patch;
}

}  // namespace fluidtex
