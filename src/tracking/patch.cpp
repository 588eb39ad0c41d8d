#include "fluidtex/tracking/patch.h"

#include <algorithm>

namespace fluidtex {

double seen_weight(const Patch& patch, std::size_t t, double radius) {
  const Tri& tri = patch.triangles[t];
  const double radial = 1.0 - ((patch.uvs[tri[0]] + patch.uvs[tri[1]] + patch.uvs[tri[2]]) / 3.0).norm() / radius;
  if (!(radial > 0.0)) return 0.0;
  const RestTriangle& r = patch.rest[t];
  return radial * triangle_area(r[0], r[1], r[2]);
}

std::vector<std::uint8_t> boundary_edge_bits(const std::vector<Tri>& triangles) {
  // Each edge listed under its lower vertex (counting sort): an edge is on
  // the boundary when its lower vertex lists its higher one once.
  int nv = 0;
  for (const Tri& t : triangles) nv = std::max({nv, t[0] + 1, t[1] + 1, t[2] + 1});
  std::vector<int> start(static_cast<std::size_t>(nv) + 1, 0);
  for (const Tri& t : triangles) {
    for (int k = 0; k < 3; ++k) ++start[static_cast<std::size_t>(std::min(t[k], t[(k + 1) % 3])) + 1];
  }
  for (int v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<int> higher(static_cast<std::size_t>(start[nv]));
  std::vector<int> next(start.begin(), start.end() - 1);
  for (const Tri& t : triangles) {
    for (int k = 0; k < 3; ++k) higher[next[std::min(t[k], t[(k + 1) % 3])]++] = std::max(t[k], t[(k + 1) % 3]);
  }
  std::vector<std::uint8_t> bits(triangles.size(), 0);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int lo = std::min(triangles[t][k], triangles[t][(k + 1) % 3]);
      const int hi = std::max(triangles[t][k], triangles[t][(k + 1) % 3]);
      if (std::count(higher.begin() + start[lo], higher.begin() + start[lo + 1], hi) == 1)
        bits[t] |= static_cast<std::uint8_t>(1u << k);
    }
  }
  return bits;
}

void update_border(Patch& patch, const SurfaceIndex& surface) {
  patch.border.assign(patch.positions.size(), 0);
  // Rim points that moved a hair inside (along a curved rim drawn with
  // chords) still count as on the rim.
  double rest_edges = 0.0;
  for (const RestTriangle& r : patch.rest) rest_edges += (r[1] - r[0]).norm();
  const double rim_tolerance = patch.rest.empty() ? 0.0 : 0.05 * rest_edges / static_cast<double>(patch.rest.size());
  const std::vector<std::uint8_t> bits = boundary_edge_bits(patch.triangles);
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      if (!(bits[t] & (1u << k))) continue;
      const int a = patch.triangles[t][k], b = patch.triangles[t][(k + 1) % 3];
      const bool rim = surface.on_boundary(patch.projections[a], rim_tolerance) &&
                       surface.on_boundary(patch.projections[b], rim_tolerance);
      if (!rim) patch.border[a] = patch.border[b] = 1;
    }
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
    if (!patch.recovery.empty()) patch.recovery[next] = patch.recovery[v];
    if (!patch.weight.empty()) patch.weight[next] = patch.weight[v];
    ++next;
  }
  patch.positions.resize(next);
  patch.projections.resize(next);
  patch.uvs.resize(next);
  if (!patch.quality.empty()) patch.quality.resize(next);
  if (!patch.recovery.empty()) patch.recovery.resize(next);
  if (!patch.weight.empty()) patch.weight.resize(next);
  for (Tri& t : triangles) {
    for (int& v : t) v = remap[v];
  }
  patch.triangles = std::move(triangles);
  patch.rest = std::move(rest);
  update_border(patch, surface);
}

}  // namespace fluidtex
