#include "fluidtex/geometry/level_set.h"

#include <mutex>
#include <utility>

#include <openvdb/tools/VolumeToMesh.h>

namespace fluidtex {

void initialize_openvdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

FrameMesh mesh_level_set(const openvdb::FloatGrid& grid, double iso, double adaptivity) {
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> tris;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(grid, points, tris, quads, iso, adaptivity);

  FrameMesh mesh;
  mesh.positions.reserve(points.size());
  for (const auto& p : points) mesh.positions.emplace_back(p.x(), p.y(), p.z());
  mesh.triangles.reserve(2 * quads.size() + tris.size());
  for (const auto& q : tris) mesh.triangles.push_back({int(q[0]), int(q[1]), int(q[2])});
  const auto& P = mesh.positions;
  for (const auto& q : quads) {
    const int a = int(q[0]), b = int(q[1]), c = int(q[2]), d = int(q[3]);
    if ((P[a] - P[c]).squaredNorm() <= (P[b] - P[d]).squaredNorm()) {
      mesh.triangles.push_back({a, b, c});
      mesh.triangles.push_back({a, c, d});
    } else {
      mesh.triangles.push_back({a, b, d});
      mesh.triangles.push_back({b, c, d});
    }
  }
  // volumeToMesh winds every polygon alike; turn them all so that the
  // enclosed volume is positive (normals out of the liquid).
  double volume6 = 0.0;
  for (const Tri& f : mesh.triangles) volume6 += P[f[0]].dot(P[f[1]].cross(P[f[2]]));
  if (volume6 < 0.0) {
    for (Tri& f : mesh.triangles) std::swap(f[1], f[2]);
  }
  mesh.velocities.assign(mesh.positions.size(), Vec3::Zero());
  return mesh;
}

}  // namespace fluidtex
