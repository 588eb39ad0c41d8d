#include "fluidtex/geometry/surface.h"

#include <algorithm>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

namespace fluidtex {

namespace {
using K = CGAL::Simple_cartesian<double>;
using Triangles = std::vector<K::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

K::Point_3 to_cgal(const Vec3& p) { return {p.x(), p.y(), p.z()}; }
}  // namespace

struct SurfaceIndex::Tree {
  Triangles triangles;
  ::fluidtex::Tree tree;
};

Vec3 barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 v0 = b - a, v1 = c - a, v2 = p - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1);
  const double d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double denom = d00 * d11 - d01 * d01;
  if (!(std::abs(denom) > 1e-300) || !(denom > 1e-14 * d00 * d11)) {
    // Degenerate: the nearest corner.
    const double da = (p - a).squaredNorm(), db = (p - b).squaredNorm(), dc = (p - c).squaredNorm();
    if (da <= db && da <= dc) return {1, 0, 0};
    return db <= dc ? Vec3(0, 1, 0) : Vec3(0, 0, 1);
  }
  double v = (d11 * d20 - d01 * d21) / denom;
  double w = (d00 * d21 - d01 * d20) / denom;
  // The point comes from a closest-point query, so it is inside up to rounding.
  v = std::clamp(v, 0.0, 1.0);
  w = std::clamp(w, 0.0, 1.0 - v);
  return {1.0 - v - w, v, w};
}

SurfaceIndex::SurfaceIndex(const FrameMesh& mesh) : mesh_(&mesh), tree_(std::make_unique<Tree>()) {
  const std::size_t nf = mesh.triangles.size();
  face_normals_.resize(nf);
  face_areas_.resize(nf);
  tree_->triangles.reserve(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const Tri& t = mesh.triangles[f];
    const Vec3 n = face_area_normal(mesh, f);
    const double len = n.norm();
    face_areas_[f] = 0.5 * len;
    face_normals_[f] = len > 0.0 ? Vec3(n / len) : Vec3(0, 0, 1);
    tree_->triangles.emplace_back(to_cgal(mesh.positions[t[0]]), to_cgal(mesh.positions[t[1]]),
                                  to_cgal(mesh.positions[t[2]]));
  }
  if (nf > 0) {
    tree_->tree.insert(tree_->triangles.cbegin(), tree_->triangles.cend());
    tree_->tree.build();
    tree_->tree.accelerate_distance_queries();  // builds now: later const queries are thread safe
  }
  vertex_normals_ = fluidtex::vertex_normals(mesh);

  // Edge adjacency: sort (min, max, face, corner) records and pair equal edges.
  struct EdgeRec {
    int a, b, face, corner;
  };
  std::vector<EdgeRec> edges;
  edges.reserve(3 * nf);
  for (std::size_t f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles[f][k], b = mesh.triangles[f][(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), static_cast<int>(f), k});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const EdgeRec& x, const EdgeRec& y) {
    return std::tie(x.a, x.b, x.face, x.corner) < std::tie(y.a, y.b, y.face, y.corner);
  });
  neighbors_.assign(nf, {-1, -1, -1});
  vertex_boundary_.assign(mesh.positions.size(), 0);
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b) ++j;
    if (j - i == 2) {
      neighbors_[edges[i].face][edges[i].corner] = edges[i + 1].face;
      neighbors_[edges[i + 1].face][edges[i + 1].corner] = edges[i].face;
    } else if (j - i == 1) {
      vertex_boundary_[edges[i].a] = vertex_boundary_[edges[i].b] = 1;
    }
    i = j;
  }

  num_components_ = face_components(mesh, component_);
  component_area_.assign(num_components_, 0.0);
  for (std::size_t f = 0; f < nf; ++f) component_area_[component_[f]] += face_areas_[f];
}

SurfaceIndex::~SurfaceIndex() = default;
SurfaceIndex::SurfaceIndex(SurfaceIndex&&) noexcept = default;
SurfaceIndex& SurfaceIndex::operator=(SurfaceIndex&&) noexcept = default;

SurfacePoint SurfaceIndex::at(int face, const Vec3& bary) const {
  SurfacePoint s;
  s.face = face;
  s.bary = bary;
  const Tri& t = mesh_->triangles[face];
  s.position = interpolate(mesh_->positions, t, bary);
  return s;
}

std::vector<int> SurfaceIndex::faces_in_box(const Vec3& lo, const Vec3& hi) const {
  std::vector<int> out;
  if (tree_->triangles.empty()) return out;
  std::vector<Primitive::Id> found;
  tree_->tree.all_intersected_primitives(K::Iso_cuboid_3(lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z()),
                                         std::back_inserter(found));
  out.reserve(found.size());
  for (const auto& it : found) out.push_back(static_cast<int>(it - tree_->triangles.cbegin()));
  std::sort(out.begin(), out.end());
  return out;
}

SurfacePoint SurfaceIndex::closest_point(const Vec3& p) const {
  SurfacePoint s;
  if (tree_->triangles.empty()) return s;
  const auto [point, primitive] = tree_->tree.closest_point_and_primitive(to_cgal(p));
  s.face = static_cast<int>(primitive - tree_->triangles.cbegin());
  s.position = Vec3(point.x(), point.y(), point.z());
  const Tri& t = mesh_->triangles[s.face];
  s.bary = barycentric(s.position, mesh_->positions[t[0]], mesh_->positions[t[1]], mesh_->positions[t[2]]);
  s.distance = (s.position - p).norm();
  return s;
}

bool SurfaceIndex::on_boundary(const SurfacePoint& s, double tolerance) const {
  constexpr double eps = 1e-9;
  const Tri& t = mesh_->triangles[s.face];
  for (int k = 0; k < 3; ++k) {
    // Edge k joins corners k and k+1; the point is on it when the opposite
    // corner's coordinate vanishes.
    if (neighbors_[s.face][k] < 0 && s.bary[(k + 2) % 3] < eps) return true;
    if (s.bary[k] > 1.0 - eps && vertex_boundary_[t[k]]) return true;
  }
  if (!(tolerance > 0.0)) return false;
  const double tol2 = tolerance * tolerance;
  for (int k = 0; k < 3; ++k) {
    const Vec3& a = mesh_->positions[t[k]];
    if (vertex_boundary_[t[k]] && (s.position - a).squaredNorm() <= tol2) return true;
    if (neighbors_[s.face][k] >= 0) continue;
    const Vec3& b = mesh_->positions[t[(k + 1) % 3]];
    const Vec3 ab = b - a;
    const double len2 = ab.squaredNorm();
    const double u = len2 > 0.0 ? std::clamp((s.position - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    if ((s.position - (a + u * ab)).squaredNorm() <= tol2) return true;
  }
  return false;
}

SurfacePoint SurfaceIndex::closest_rim_point(const Vec3& p, double radius) const {
  SurfacePoint best;
  double best2 = radius * radius;
  const Vec3 reach = Vec3::Constant(radius);
  for (int f : faces_in_box(p - reach, p + reach)) {
    const Tri& t = mesh_->triangles[f];
    for (int k = 0; k < 3; ++k) {
      if (neighbors_[f][k] >= 0) continue;
      const Vec3& a = mesh_->positions[t[k]];
      const Vec3 ab = mesh_->positions[t[(k + 1) % 3]] - a;
      const double len2 = ab.squaredNorm();
      const double u = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
      const double d2 = (p - (a + u * ab)).squaredNorm();
      if (best.valid() ? !(d2 < best2) : d2 > best2) continue;  // the first of equals
      Vec3 bary = Vec3::Zero();
      bary[k] = 1.0 - u, bary[(k + 1) % 3] = u;
      best = at(f, bary);
      best.distance = std::sqrt(d2);
      best2 = d2;
    }
  }
  return best;
}

Vec3 SurfaceIndex::normal_at(const SurfacePoint& s) const {
  const Tri& t = mesh_->triangles[s.face];
  const Vec3 n = interpolate(vertex_normals_, t, s.bary);
  const double len = n.norm();
  // A blend that vanishes or points behind the face (a face folded against
  // its vertices' normals, as a crease of a re-meshed splash makes) is no
  // normal of this point: the face's own is. A face without area has no
  // normal of its own to judge the blend by.
  const bool folded = face_areas_[s.face] > 0.0 && !(n.dot(face_normals_[s.face]) > 0.0);
  return len > 1e-12 && !folded ? Vec3(n / len) : face_normals_[s.face];
}

Vec3 SurfaceIndex::velocity_at(const SurfacePoint& s) const {
  const Tri& t = mesh_->triangles[s.face];
  return interpolate(mesh_->velocities, t, s.bary);
}

}  // namespace fluidtex
