#include "fluidtex/patch.h"

#include <algorithm>

namespace fluidtex {

void update_border(Patch& patch, const SurfaceIndex& surface) {
  struct Edge {
    int a, b;
  };
  std::vector<Edge> edges;
  edges.reserve(3 * patch.triangles.size());
  for (const Tri& t : patch.triangles) {
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; });
  patch.border.assign(patch.positions.size(), 0);
  // Rim points that moved a hair inside (along a curved rim drawn with
  // chords) still count as on the rim.
  double rest_edges = 0.0;
  for (const RestTriangle& r : patch.rest) rest_edges += (r[1] - r[0]).norm();
  const double rim_tolerance = patch.rest.empty() ? 0.0 : 0.05 * rest_edges / static_cast<double>(patch.rest.size());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b) ++j;
    const int a = edges[i].a, b = edges[i].b;
    const bool rim = surface.on_boundary(patch.projections[a], rim_tolerance) &&
                     surface.on_boundary(patch.projections[b], rim_tolerance);
    if (j - i == 1 && !rim) patch.border[a] = patch.border[b] = 1;
    i = j;
  }
}

void remove_vertices(Patch& patch, const std::vector<std::uint8_t>& keep, const SurfaceIndex& surface) {
  std::vector<std::uint8_t> keep_triangle(patch.triangles.size());
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    const Tri& tri = patch.triangles[t];
    keep_triangle[t] = keep[tri[0]] && keep[tri[1]] && keep[tri[2]];
  }
  remove_triangles(patch, keep_triangle, surface);
}

void remove_triangles(Patch& patch, const std::vector<std::uint8_t>& keep, const SurfaceIndex& surface) {
  const std::size_t nv = patch.positions.size();
  std::vector<std::uint8_t> used(nv, 0);
  std::vector<Tri> triangles;
  std::vector<RestTriangle> rest;
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    const Tri& tri = patch.triangles[t];
    if (keep[t]) {
      triangles.push_back(tri);
      rest.push_back(patch.rest[t]);
      used[tri[0]] = used[tri[1]] = used[tri[2]] = 1;
    }
  }
  std::vector<int> remap(nv, -1);
  int next = 0;
  for (std::size_t v = 0; v < nv; ++v) {
    if (!used[v]) continue;
    remap[v] = next;
    patch.positions[next] = patch.positions[v];
    patch.projections[next] = patch.projections[v];
    patch.uvs[next] = patch.uvs[v];
    if (!patch.quality.empty()) patch.quality[next] = patch.quality[v];
    if (!patch.weight.empty()) patch.weight[next] = patch.weight[v];
    ++next;
  }
  patch.positions.resize(next);
  patch.projections.resize(next);
  patch.uvs.resize(next);
  if (!patch.quality.empty()) patch.quality.resize(next);
  if (!patch.weight.empty()) patch.weight.resize(next);
  for (Tri& t : triangles) {
    for (int& v : t) v = remap[v];
  }
  patch.triangles = std::move(triangles);
  patch.rest = std::move(rest);
  update_border(patch, surface);
}

}  // namespace fluidtex
