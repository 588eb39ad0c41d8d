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

/// A region grown face by face that stays a topological disk: what it holds
/// (faces, vertices, its edges' face counts and the boundary's direction)
/// and the faces waiting, by priority.
class DiskRegion {
 public:
  DiskRegion(const SurfaceIndex& surface, const DiskRegionOptions& options) : surface_(surface), options_(options) {}

  std::vector<int> grow(int seed) {
    add(seed);
    while (!queue_.empty() && (options_.max_faces == 0 || order_.size() < options_.max_faces)) {
      const int f = queue_.top().second;
      queue_.pop();
      if (in_region_.count(f) || rejected_.count(f)) continue;
      if (!options_.accept(f)) {
        rejected_.insert(f);
        continue;
      }
      // A face that would leave the region a disk joins; one on an edge
      // already interior or against the boundary's direction never can;
      // other cases (a hole or handle would appear) may become valid when a
      // neighbour joins, and the face is pushed again then.
      const Join join = joins(f);
      if (join == Join::Never) rejected_.insert(f);
      if (join == Join::Now) add(f);
    }
    return std::move(order_);
  }

 private:
  enum class Join { Now, Later, Never };

  void add(int f) {
    const Tri& t = surface_.mesh().triangles[f];
    in_region_.insert(f);
    order_.push_back(f);
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      const std::uint64_t key = edge_key(a, b);
      if (++edge_faces_[key] == 1) edge_from_[key] = a;
      region_vertices_.insert(a);
    }
    for (int g : surface_.face_neighbors()[f]) {
      if (g >= 0 && !in_region_.count(g) && !rejected_.count(g)) queue_.emplace(options_.priority(g), g);
    }
  }

  Join joins(int f) {
    const Tri& t = surface_.mesh().triangles[f];
    int boundary = 0, corners = 0;
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      const auto it = edge_faces_.find(edge_key(a, b));
      if (it == edge_faces_.end()) continue;
      if (it->second >= 2) return Join::Never;                  // edge already interior: non-manifold
      if (edge_from_[edge_key(a, b)] == a) return Join::Never;  // same direction: inconsistent orientation
      ++boundary;
    }
    for (int v : t) corners += region_vertices_.count(v) ? 1 : 0;
    return (boundary == 1 && corners == 2) || (boundary == 2 && corners == 3) ? Join::Now : Join::Later;
  }

  const SurfaceIndex& surface_;
  const DiskRegionOptions& options_;
  std::unordered_map<std::uint64_t, int> edge_faces_;  // region faces per edge (1 = boundary)
  std::unordered_map<std::uint64_t, int> edge_from_;   // for boundary edges: the directed start vertex
  std::unordered_set<int> region_vertices_, in_region_, rejected_;
  std::vector<int> order_;
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue_;
};

}  // namespace

std::vector<int> grow_disk_region(const SurfaceIndex& surface, int seed, const DiskRegionOptions& options) {
  return DiskRegion(surface, options).grow(seed);
}

}  // namespace fluidtex
