#include "fluidtex/geometry/parameterization.h"

#include <cmath>
#include <unordered_map>

#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>

namespace fluidtex {

namespace {

using K = CGAL::Simple_cartesian<double>;
using SM = CGAL::Surface_mesh<K::Point_3>;
using VD = SM::Vertex_index;

/// Builds a Surface_mesh whose vertex i is mesh.positions[i]; false when a
/// face cannot be added (non-manifold or inconsistently oriented input).
bool to_surface_mesh(const DiskMesh& mesh, SM& sm) {
  sm.clear();
  for (const Vec3& p : mesh.positions) sm.add_vertex(K::Point_3(p.x(), p.y(), p.z()));
  for (const Tri& t : mesh.triangles) {
    if (sm.add_face(VD(t[0]), VD(t[1]), VD(t[2])) == SM::null_face()) return false;
  }
  return true;
}

}  // namespace

DiskMesh extract_faces(const FrameMesh& mesh, const std::vector<int>& faces) {
  DiskMesh out;
  std::unordered_map<int, int> local;
  for (int f : faces) {
    Tri t;
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles[f][k];
      auto [it, inserted] = local.emplace(v, static_cast<int>(out.positions.size()));
      if (inserted) out.positions.push_back(mesh.positions[v]);
      t[k] = it->second;
    }
    out.triangles.push_back(t);
  }
  return out;
}

bool flatten_lscm(const DiskMesh& mesh, std::vector<Vec2>& uvs, std::string* failure) {
  auto fail = [&](const char* why) {
    if (failure) *failure = why;
    return false;
  };
  SM sm;
  if (!to_surface_mesh(mesh, sm)) return fail("not a manifold, consistently oriented mesh");
  SM::Halfedge_index border = SM::null_halfedge();
  for (SM::Halfedge_index h : sm.halfedges()) {
    if (sm.is_border(h)) {
      border = h;
      break;
    }
  }
  if (border == SM::null_halfedge()) return fail("no boundary (closed surface)");
  auto uvmap = sm.add_property_map<VD, K::Point_2>("v:uv").first;
  namespace SMP = CGAL::Surface_mesh_parameterization;
  if (SMP::parameterize(sm, SMP::LSCM_parameterizer_3<SM>(), border, uvmap) != SMP::OK) {
    return fail("LSCM solve failed");
  }
  uvs.resize(mesh.positions.size());
  for (std::size_t v = 0; v < uvs.size(); ++v) uvs[v] = Vec2(uvmap[VD(v)].x(), uvmap[VD(v)].y());

  double area3 = 0.0, area_uv = 0.0;
  for (const Tri& t : mesh.triangles) {
    area3 += triangle_area(mesh.positions, t);
    area_uv += signed_area(uvs[t[0]], uvs[t[1]], uvs[t[2]]);
  }
  if (!(std::abs(area_uv) > 0.0) || !(area3 > 0.0) || !std::isfinite(area_uv))
    return fail("degenerate parameterisation");
  const double scale = std::sqrt(area3 / std::abs(area_uv));
  const double mirror = area_uv < 0.0 ? -1.0 : 1.0;
  for (Vec2& uv : uvs) uv = Vec2(mirror * uv.x(), uv.y()) * scale;
  return true;
}

bool remesh_disk(DiskMesh& mesh, double edge_length, int iterations) {
  SM sm;
  if (!to_surface_mesh(mesh, sm)) return false;
  namespace PMP = CGAL::Polygon_mesh_processing;
  PMP::isotropic_remeshing(
      sm.faces(), edge_length, sm,
      CGAL::parameters::number_of_iterations(static_cast<unsigned>(iterations)).collapse_constraints(false));
  sm.collect_garbage();
  DiskMesh out;
  std::unordered_map<std::uint32_t, int> index;
  for (VD v : sm.vertices()) {
    index.emplace(static_cast<std::uint32_t>(v), static_cast<int>(out.positions.size()));
    const K::Point_3& p = sm.point(v);
    out.positions.emplace_back(p.x(), p.y(), p.z());
  }
  for (SM::Face_index f : sm.faces()) {
    Tri t{};
    int k = 0;
    for (VD v : CGAL::vertices_around_face(sm.halfedge(f), sm)) t[k++] = index.at(static_cast<std::uint32_t>(v));
    out.triangles.push_back(t);
  }
  mesh = std::move(out);
  return true;
}

}  // namespace fluidtex
