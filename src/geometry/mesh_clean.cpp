// Minimal, deterministic repair of a reconstructed surface (see mesh_clean.h).
// Every step is a sort or a hash lookup over plain arrays: O(n log n) at worst.

#include "fluidtex/geometry/mesh_clean.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>

namespace fluidtex {

namespace {

/// "1 vertex" / "3 vertices".
std::string count_of(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

struct CellKey {
  std::int64_t x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};

struct CellHash {
  std::size_t operator()(const CellKey& k) const {
    std::uint64_t h = static_cast<std::uint64_t>(k.x) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<std::uint64_t>(k.y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= static_cast<std::uint64_t>(k.z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return static_cast<std::size_t>(h);
  }
};

/// Maps every vertex to its representative: the lowest-index vertex within
/// `tol` of it that is itself a representative (greedy, in index order, so
/// the result does not depend on hashing). With tol == 0 only bit-identical
/// positions merge. A hash grid of cell size 2·tol means the tol-ball around a
/// point touches at most two cells per axis.
std::vector<int> find_representatives(const std::vector<Vec3>& p, double tol) {
  const int n = static_cast<int>(p.size());
  std::vector<int> rep(n);
  const double cell = tol > 0.0 ? 2.0 * tol : 1.0;
  auto key_of = [&](double v) {
    // With tol == 0 the key is the exact bit pattern (+0 and -0 unified).
    if (tol <= 0.0) {
      const double u = v == 0.0 ? 0.0 : v;
      std::int64_t bits;
      static_assert(sizeof(bits) == sizeof(u));
      std::memcpy(&bits, &u, sizeof(bits));
      return bits;
    }
    return static_cast<std::int64_t>(std::floor(v / cell));
  };
  std::unordered_map<CellKey, std::vector<int>, CellHash> grid;
  grid.reserve(p.size());
  const double tol2 = tol * tol;
  for (int i = 0; i < n; ++i) {
    int best = -1;
    std::int64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = key_of(tol > 0.0 ? p[i][a] - tol : p[i][a]);
      hi[a] = key_of(tol > 0.0 ? p[i][a] + tol : p[i][a]);
    }
    for (std::int64_t x = lo[0]; x <= hi[0]; ++x)
      for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
        for (std::int64_t z = lo[2]; z <= hi[2]; ++z) {
          auto it = grid.find({x, y, z});
          if (it == grid.end()) continue;
          for (int j : it->second) {
            if ((best < 0 || j < best) && (p[j] - p[i]).squaredNorm() <= tol2) best = j;
          }
        }
    if (best >= 0) {
      rep[i] = best;
    } else {
      rep[i] = i;
      grid[{key_of(p[i][0]), key_of(p[i][1]), key_of(p[i][2])}].push_back(i);
    }
  }
  return rep;
}

}  // namespace

std::string CleanReport::summary() const {
  if (!changed() && nonmanifold_edges == 0 && boundary_edges == 0 && components <= 1) return "clean";
  std::ostringstream s;
  s << "merged " << count_of(merged_vertices, "vertex", "vertices") << ", dropped " << degenerate_faces
    << " degenerate and " << count_of(duplicate_faces, "duplicate face", "duplicate faces") << ", "
    << count_of(unreferenced_vertices, "unreferenced vertex", "unreferenced vertices") << "; "
    << count_of(nonmanifold_edges, "non-manifold edge", "non-manifold edges") << ", "
    << count_of(boundary_edges, "boundary edge", "boundary edges") << ", "
    << count_of(static_cast<std::size_t>(std::max(components, 0)), "component", "components");
  return s.str();
}

namespace {

/// Step 2: triangles remapped to representatives, without repeated-index and
/// zero-area ones. The area threshold is relative to the scene size so it is
/// unit-independent.
std::vector<Tri> remap_triangles(const FrameMesh& mesh, const std::vector<int>& rep, double min_area,
                                 CleanReport& report) {
  std::vector<Tri> kept;
  kept.reserve(mesh.triangles.size());
  for (const Tri& t0 : mesh.triangles) {
    const Tri t = {rep[t0[0]], rep[t0[1]], rep[t0[2]]};
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      ++report.degenerate_faces;
      continue;
    }
    const double area = triangle_area(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
    if (!(area > min_area)) {
      ++report.degenerate_faces;
      continue;
    }
    kept.push_back(t);
  }
  return kept;
}

/// Step 3: duplicates (same vertex set, any orientation) dropped; the first kept.
void drop_duplicate_faces(std::vector<Tri>& kept, CleanReport& report) {
  std::vector<std::pair<Tri, std::size_t>> keyed(kept.size());
  for (std::size_t f = 0; f < kept.size(); ++f) {
    Tri k = kept[f];
    std::sort(k.begin(), k.end());
    keyed[f] = {k, f};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<char> drop(kept.size(), 0);
  for (std::size_t i = 1; i < keyed.size(); ++i) {
    if (keyed[i].first == keyed[i - 1].first) drop[keyed[i].second] = 1;
  }
  std::size_t out = 0;
  for (std::size_t f = 0; f < kept.size(); ++f) {
    if (drop[f])
      ++report.duplicate_faces;
    else
      kept[out++] = kept[f];
  }
  kept.resize(out);
}

/// Step 5: boundary and non-manifold edges counted (reported, not repaired).
void count_edges(const FrameMesh& mesh, CleanReport& report) {
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const Tri& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const auto a = static_cast<std::uint64_t>(std::min(t[k], t[(k + 1) % 3]));
      const auto b = static_cast<std::uint64_t>(std::max(t[k], t[(k + 1) % 3]));
      edges.push_back((a << 32) | b);
    }
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) ++report.boundary_edges;
    if (j - i > 2) ++report.nonmanifold_edges;
    i = j;
  }
}

}  // namespace

CleanReport clean_mesh(FrameMesh& mesh, const CleanOptions& options) {
  CleanReport report;
  const std::size_t nv = mesh.positions.size();
  if (mesh.velocities.size() != nv) mesh.velocities.resize(nv, Vec3::Zero());
  const double diag = bounding_box(mesh).diagonal();

  // 1. Merge coincident vertices; representatives get the mean velocity.
  const std::vector<int> rep = find_representatives(mesh.positions, options.merge_tolerance * diag);
  std::vector<int> members(nv, 0);
  std::vector<Vec3> vel_sum(nv, Vec3::Zero());
  for (std::size_t i = 0; i < nv; ++i) {
    members[rep[i]] += 1;
    vel_sum[rep[i]] += mesh.velocities[i];
    if (rep[i] != static_cast<int>(i)) ++report.merged_vertices;
  }
  // 2–3. Degenerate and duplicate faces.
  std::vector<Tri> kept = remap_triangles(mesh, rep, options.degenerate_area * diag * diag, report);
  drop_duplicate_faces(kept, report);

  // 4. Compact: keep referenced representatives in their original order.
  std::vector<char> used(nv, 0);
  for (const Tri& t : kept)
    for (int v : t) used[v] = 1;
  std::vector<int> new_index(nv, -1);
  FrameMesh out;
  for (std::size_t i = 0; i < nv; ++i) {
    if (rep[i] != static_cast<int>(i)) continue;  // merged away: already counted
    if (!used[i]) {
      ++report.unreferenced_vertices;
      continue;
    }
    new_index[i] = static_cast<int>(out.positions.size());
    out.positions.push_back(mesh.positions[i]);
    out.velocities.emplace_back(vel_sum[i] / static_cast<double>(members[i]));
  }
  out.triangles.reserve(kept.size());
  for (const Tri& t : kept) out.triangles.push_back({new_index[t[0]], new_index[t[1]], new_index[t[2]]});
  mesh = std::move(out);

  // 5. Report (not repair) edge manifoldness and components.
  count_edges(mesh, report);
  std::vector<int> component_of_face;
  report.components = face_components(mesh, component_of_face);
  return report;
}

}  // namespace fluidtex
