#include "fluidtex/geometry/mesh.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <tuple>

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

namespace {

/// `a` if it lies in the slab, and where a→b crosses the slab's lines,
/// computed from `a`.
void edge_in_slab(const Vec2& a, const Vec2& b, int axis, double s0, double s1, double& lo, double& hi) {
  const int other = 1 - axis;
  const auto take = [&](double v) { lo = std::min(lo, v), hi = std::max(hi, v); };
  if (a[axis] >= s0 && a[axis] <= s1) take(a[other]);
  for (const double s : {s0, s1}) {
    if ((a[axis] < s && b[axis] > s) || (a[axis] > s && b[axis] < s))
      take(a[other] + (s - a[axis]) / (b[axis] - a[axis]) * (b[other] - a[other]));
  }
}

}  // namespace

void segment_slab_extent(const Vec2& a, const Vec2& b, int axis, double s0, double s1, double& lo, double& hi) {
  edge_in_slab(a, b, axis, s0, s1, lo, hi);
  if (b[axis] >= s0 && b[axis] <= s1) lo = std::min(lo, b[1 - axis]), hi = std::max(hi, b[1 - axis]);
}

bool slab_extent(const std::array<Vec2, 3>& t, int axis, double s0, double s1, double& lo, double& hi) {
  lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int k = 0; k < 3; ++k) edge_in_slab(t[k], t[(k + 1) % 3], axis, s0, s1, lo, hi);
  return lo <= hi;
}

FlatOutline flat_outline(const std::vector<Tri>& tris, const std::vector<std::array<Vec2, 3>>& corners) {
  FlatOutline out;
  std::vector<double> area(tris.size());
  double orientation = 0.0;
  for (std::size_t i = 0; i < tris.size(); ++i) {
    area[i] = signed_area(corners[i][0], corners[i][1], corners[i][2]);
    orientation += area[i];
  }
  struct Edge {
    int lo, hi, edge;
    bool forward;
  };
  std::vector<Edge> edges;
  edges.reserve(3 * tris.size());
  for (std::size_t i = 0; i < tris.size(); ++i) {
    if (!(area[i] * orientation > 0.0)) {
      out.loose_faces.push_back(static_cast<int>(i));
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const int a = tris[i][k], b = tris[i][(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), static_cast<int>(3 * i) + k, a < b});
    }
  }
  std::sort(edges.begin(), edges.end(),
            [](const Edge& x, const Edge& y) { return std::tie(x.lo, x.hi, x.edge) < std::tie(y.lo, y.hi, y.edge); });
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
    const bool inner = j - i == 2 && edges[i].forward != edges[i + 1].forward;
    if (!inner) {
      for (std::size_t k = i; k < j; ++k) out.border_edges.push_back(edges[k].edge);
    }
    i = j;
  }
  std::sort(out.border_edges.begin(), out.border_edges.end());
  return out;
}

}  // namespace fluidtex
