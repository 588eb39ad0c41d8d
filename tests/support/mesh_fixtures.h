// Small procedural meshes for the tracking tests.
#pragma once

#include <cmath>
#include <functional>

#include "fluidtex/geometry/mesh.h"
#include "fluidtex/geometry/uv_mesh.h"

namespace fluidtex::test {

/// A flat n×n grid over [x0, x0+size]×[y0, y0+size] at height z (normal +z),
/// with velocities from `velocity(position)`.
inline FrameMesh flat_grid(int n, double size = 1.0, double z = 0.0, double x0 = 0.0, double y0 = 0.0,
                           const std::function<Vec3(const Vec3&)>& velocity = nullptr, bool flip = false) {
  FrameMesh m;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const Vec3 p(x0 + size * i / n, y0 + size * j / n, z);
      m.positions.push_back(p);
      m.velocities.push_back(velocity ? velocity(p) : Vec3::Zero());
    }
  }
  auto id = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      Tri a{id(i, j), id(i + 1, j), id(i + 1, j + 1)};
      Tri b{id(i, j), id(i + 1, j + 1), id(i, j + 1)};
      if (flip) std::swap(a[1], a[2]), std::swap(b[1], b[2]);
      m.triangles.push_back(a);
      m.triangles.push_back(b);
    }
  }
  return m;
}

/// Appends `b` to `a` (a second component).
inline void append(FrameMesh& a, const FrameMesh& b) {
  const int off = static_cast<int>(a.positions.size());
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  a.velocities.insert(a.velocities.end(), b.velocities.begin(), b.velocities.end());
  for (Tri t : b.triangles) a.triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
}

/// A UV sphere of radius r centred at c (outward normals).
inline FrameMesh uv_sphere(int rings, int segments, double r, const Vec3& c = Vec3::Zero()) {
  FrameMesh m;
  m.positions.push_back(c + Vec3(0, 0, r));
  for (int i = 1; i < rings; ++i) {
    const double th = M_PI * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double ph = 2 * M_PI * j / segments;
      m.positions.push_back(c + r * Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
    }
  }
  m.positions.push_back(c + Vec3(0, 0, -r));
  const int south = static_cast<int>(m.positions.size()) - 1;
  auto ring = [&](int i, int j) { return 1 + (i - 1) * segments + (j % segments); };
  for (int j = 0; j < segments; ++j) m.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
  for (int i = 1; i < rings - 1; ++i) {
    for (int j = 0; j < segments; ++j) {
      m.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  }
  for (int j = 0; j < segments; ++j) m.triangles.push_back({south, ring(rings - 1, j + 1), ring(rings - 1, j)});
  m.velocities.assign(m.positions.size(), Vec3::Zero());
  return m;
}

/// A flat n×n grid over [x0, x0+1]×[0,1] whose uvs are fixed to its
/// vertices (uv = vertex position at x0 = 0): moving x0 moves the texture
/// with the surface.
inline UVMesh textured_grid(int n, double x0) {
  const FrameMesh grid = flat_grid(n, 1.0, 0.0, x0, 0.0);
  UVMesh m;
  m.positions = grid.positions;
  m.normals.assign(grid.positions.size(), Vec3::UnitZ());
  m.triangles = grid.triangles;
  for (const Vec3& p : grid.positions) m.uvs.emplace_back(p.x() - x0, p.y());
  m.uv_triangles = grid.triangles;
  return m;
}

}  // namespace fluidtex::test
