#include "fluidtex/geometry/mesh.h"

#include <limits>
#include <numeric>

#include <Eigen/Geometry>

namespace fluidtex {

BBox bounding_box(const FrameMesh& mesh) { return bounding_box(mesh.positions); }

BBox bounding_box(const std::vector<Vec3>& positions) {
  BBox box;
  if (positions.empty()) return box;
  box.min = box.max = positions.front();
  for (const Vec3& p : positions) {
    box.min = box.min.cwiseMin(p);
    box.max = box.max.cwiseMax(p);
  }
  return box;
}

Vec3 face_area_normal(const FrameMesh& mesh, std::size_t face) {
  const Tri& t = mesh.triangles[face];
  const Vec3& a = mesh.positions[t[0]];
  return (mesh.positions[t[1]] - a).cross(mesh.positions[t[2]] - a);
}

double surface_area(const FrameMesh& mesh) {
  double area = 0.0;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) area += 0.5 * face_area_normal(mesh, f).norm();
  return area;
}

double mean_edge_length(const FrameMesh& mesh) {
  if (mesh.triangles.empty()) return 0.0;
  double sum = 0.0;
  for (const Tri& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) sum += (mesh.positions[t[k]] - mesh.positions[t[(k + 1) % 3]]).norm();
  }
  return sum / (3.0 * static_cast<double>(mesh.triangles.size()));
}

std::vector<Vec3> vertex_normals(const FrameMesh& mesh) {
  std::vector<Vec3> normals(mesh.positions.size(), Vec3::Zero());
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const Vec3 n = face_area_normal(mesh, f);
    for (int v : mesh.triangles[f]) normals[v] += n;
  }
  for (Vec3& n : normals) {
    const double len = n.norm();
    if (len > 0.0) n /= len;
  }
  return normals;
}

int face_components(const FrameMesh& mesh, std::vector<int>& component_of_face) {
  // Union-find over vertices, then label faces by their first vertex's root.
  std::vector<int> parent(mesh.positions.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const Tri& t : mesh.triangles) {
    for (int k = 1; k < 3; ++k) {
      const int a = find(t[0]), b = find(t[k]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  std::vector<int> label(mesh.positions.size(), -1);
  component_of_face.assign(mesh.triangles.size(), -1);
  int count = 0;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const int root = find(mesh.triangles[f][0]);
    if (label[root] < 0) label[root] = count++;
    component_of_face[f] = label[root];
  }
  return count;
}

bool slab_extent(const std::array<Vec2, 3>& t, int axis, double s0, double s1, double& lo, double& hi) {
  const int other = 1 - axis;
  lo = std::numeric_limits<double>::infinity(), hi = -lo;
  const auto take = [&](double v) { lo = std::min(lo, v), hi = std::max(hi, v); };
  for (int k = 0; k < 3; ++k) {
    const Vec2 &a = t[k], &b = t[(k + 1) % 3];
    if (a[axis] >= s0 && a[axis] <= s1) take(a[other]);
    for (const double s : {s0, s1}) {
      if ((a[axis] < s && b[axis] > s) || (a[axis] > s && b[axis] < s))
        take(a[other] + (s - a[axis]) / (b[axis] - a[axis]) * (b[other] - a[other]));
    }
  }
  return lo <= hi;
}

}  // namespace fluidtex
