#include "fluidtex/geometry/disk_region.h"

#include <algorithm>
#include <queue>
#include <unordered_map>
#include <unordered_set>

namespace fluidtex {

namespace {

std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint32_t>(std::min(a, b));
  const auto hi = static_cast<std::uint32_t>(std::max(a, b));
  return (static_cast<std::uint64_t>(lo) << 32) | hi;
}

}  // namespace

std::vector<int> grow_disk_region(const SurfaceIndex& surface, int seed, const DiskRegionOptions& options) {
  const FrameMesh& mesh = surface.mesh();
  std::unordered_map<std::uint64_t, int> edge_faces;  // region faces per edge (1 = boundary)
  std::unordered_map<std::uint64_t, int> edge_from;   // for boundary edges: the directed start vertex
  std::unordered_set<int> region_vertices, in_region, rejected;
  std::vector<int> order;

  auto add = [&](int f) {
    const Tri& t = mesh.triangles[f];
    in_region.insert(f);
    order.push_back(f);
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      const std::uint64_t key = edge_key(a, b);
      if (++edge_faces[key] == 1) edge_from[key] = a;
      region_vertices.insert(a);
    }
  };
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  auto push_neighbors = [&](int f) {
    for (int g : surface.face_neighbors()[f]) {
      if (g >= 0 && !in_region.count(g) && !rejected.count(g)) queue.emplace(options.priority(g), g);
    }
  };

  add(seed);
  push_neighbors(seed);
  while (!queue.empty() && (options.max_faces == 0 || order.size() < options.max_faces)) {
    const int f = queue.top().second;
    queue.pop();
    if (in_region.count(f) || rejected.count(f)) continue;
    if (!options.accept(f)) {
      rejected.insert(f);
      continue;
    }
    const Tri& t = mesh.triangles[f];
    int boundary = 0, corners = 0;
    bool ok = true;
    for (int k = 0; k < 3 && ok; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      const auto it = edge_faces.find(edge_key(a, b));
      if (it == edge_faces.end()) continue;
      if (it->second >= 2)
        ok = false;  // edge already interior: non-manifold
      else if (edge_from[edge_key(a, b)] == a)
        ok = false;  // same direction: inconsistent orientation
      else
        ++boundary;
    }
    if (!ok) {
      rejected.insert(f);
      continue;
    }
    for (int v : t) corners += region_vertices.count(v) ? 1 : 0;
    // Other cases (a hole or handle would appear) may become valid when a
    // neighbour joins; the face is pushed again then.
    if ((boundary == 1 && corners == 2) || (boundary == 2 && corners == 3)) {
      add(f);
      push_neighbors(f);
    }
  }
  return order;
}

}  // namespace fluidtex
