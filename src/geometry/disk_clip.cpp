#include "fluidtex/geometry/disk_clip.h"

#include <limits>
#include <unordered_map>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/clip.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Surface_mesh.h>

namespace fluidtex {

namespace {

// Clipping corefines the mesh with the cube: it needs exact predicates.
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using SM = CGAL::Surface_mesh<K::Point_3>;
using VD = SM::Vertex_index;
using FD = SM::Face_index;

Vec3 to_vec(const K::Point_3& p) { return {p.x(), p.y(), p.z()}; }

/// The face of `sm` whose centroid lies nearest to `centre`.
FD nearest_face(const SM& sm, const Vec3& centre) {
  FD best;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (FD f : sm.faces()) {
    Vec3 c = Vec3::Zero();
    int n = 0;
    for (VD v : sm.vertices_around_face(sm.halfedge(f))) c += to_vec(sm.point(v)), ++n;
    const double d2 = (c / n - centre).squaredNorm();
    if (d2 < best_d2) best_d2 = d2, best = f;
  }
  return best;
}

}  // namespace

bool clip_disk_to_cube(DiskMesh& disk, const Vec3& centre, double half) {
  const Vec3 lo = centre - Vec3::Constant(half), hi = centre + Vec3::Constant(half);
  bool outside = false;
  for (const Vec3& p : disk.positions)
    outside = outside || (p.array() < lo.array()).any() || (p.array() > hi.array()).any();
  if (!outside) return false;
  SM sm;
  for (const Vec3& p : disk.positions) sm.add_vertex(K::Point_3(p.x(), p.y(), p.z()));
  for (const Tri& t : disk.triangles) {
    if (sm.add_face(VD(t[0]), VD(t[1]), VD(t[2])) == SM::null_face()) return false;
  }
  namespace PMP = CGAL::Polygon_mesh_processing;
  const K::Iso_cuboid_3 cube(K::Point_3(lo.x(), lo.y(), lo.z()), K::Point_3(hi.x(), hi.y(), hi.z()));
  if (!PMP::clip(sm, cube, CGAL::parameters::clip_volume(false))) return false;
  if (sm.number_of_faces() == 0) return false;
  auto component = sm.add_property_map<FD, std::size_t>("f:component", 0).first;
  PMP::connected_components(sm, component);
  const std::size_t keep = component[nearest_face(sm, centre)];
  DiskMesh out;
  std::unordered_map<std::size_t, int> local;
  for (FD f : sm.faces()) {
    if (component[f] != keep) continue;
    std::vector<int> corners;
    for (VD v : sm.vertices_around_face(sm.halfedge(f))) {
      auto [it, inserted] = local.emplace(static_cast<std::size_t>(v), static_cast<int>(out.positions.size()));
      if (inserted) out.positions.push_back(to_vec(sm.point(v)));
      corners.push_back(it->second);
    }
    // Clipping leaves triangles; a polygon would be fanned.
    for (std::size_t k = 1; k + 1 < corners.size(); ++k)
      out.triangles.push_back({corners[0], corners[k], corners[k + 1]});
  }
  disk = std::move(out);
  return true;
}

}  // namespace fluidtex
