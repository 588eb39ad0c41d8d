/// @file mesh.h
/// @brief The per-frame surface: a triangle soup with per-vertex velocities.
///
/// Every frame of a fluid sequence is an independent mesh (implicit-surface
/// reconstruction): vertex counts and connectivity change from frame to frame.
/// The mesh may be non-manifold, have boundaries and several components; the
/// stages that need a manifold neighbourhood (patch creation, the atlas) build
/// it locally. Positions in scene units, velocities in scene units per second.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <type_traits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace fluidtex {

using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;
using Tri = std::array<int, 3>;

/// Signed area of the 2D triangle (a, b, c): positive when counter-clockwise.
inline double signed_area(const Vec2& a, const Vec2& b, const Vec2& c) {
  const Vec2 e1 = b - a, e2 = c - a;
  return 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
}

/// Area of the 2D triangle (a, b, c).
inline double triangle_area(const Vec2& a, const Vec2& b, const Vec2& c) { return std::abs(signed_area(a, b, c)); }

/// Area of triangle `t` of the 2D `points`.
inline double triangle_area(const std::vector<Vec2>& points, const Tri& t) {
  return triangle_area(points[t[0]], points[t[1]], points[t[2]]);
}

/// The extent of the 2D triangle `t` within the slab s0 ≤ p[axis] ≤ s1,
/// along the other axis (axis 0: a vertical slab, its y range; axis 1: a
/// horizontal band, its x range), in `lo`, `hi`; false when they do not
/// meet. The triangle's part in the slab is convex, with its corners among
/// the triangle's corners in the slab and the edges' crossings of the
/// slab's two lines.
bool slab_extent(const std::array<Vec2, 3>& t, int axis, double s0, double s1, double& lo, double& hi);

/// The same for the segment a→b, widening `lo`, `hi` (start them empty:
/// lo = +inf, hi = -inf). The crossings are computed from `a`, as
/// `slab_extent` does along a triangle's edge a→b, so the triangle's
/// extent is exactly the union of its three edges'.
void segment_slab_extent(const Vec2& a, const Vec2& b, int axis, double s0, double s1, double& lo, double& hi);

/// What bounds a triangle mesh laid in the plane (a chart): the extent of
/// its faces in any slab, the union of theirs, is reached on the border of
/// that union. Where the faces keep one orientation, two faces meeting at an
/// edge lie on its two sides and cover every point of it and of the corners
/// inside, so the border is among the edges of one face only (or of three
/// or more, or of two turned the same way) and the edges of the faces turned
/// against the others or flat. A disk of n faces has about √n such edges.
struct FlatOutline {
  std::vector<int> border_edges;  ///< face·3 + k: corner k → corner k + 1 of that face, ascending
  std::vector<int> loose_faces;   ///< faces turned against the mesh's orientation, or flat, ascending
};

/// The outline of the faces `tris` (vertex indices) laid at `corners`
/// (per face, its corners' flat positions; one position per vertex).
FlatOutline flat_outline(const std::vector<Tri>& tris, const std::vector<std::array<Vec2, 3>>& corners);

/// Area of the 3D triangle (a, b, c).
inline double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * (b - a).cross(c - a).norm(); }

/// Area of triangle `t` of `positions`.
inline double triangle_area(const std::vector<Vec3>& positions, const Tri& t) {
  return triangle_area(positions[t[0]], positions[t[1]], positions[t[2]]);
}

/// l[0]·a + l[1]·b + l[2]·c: a value at barycentric coordinates `l` of a
/// triangle with corner values a, b, c (positions, uvs, normals, weights).
/// Scalars (float included) interpolate in double.
template <class T>
auto interpolate(const Vec3& l, const T& a, const T& b, const T& c) {
  if constexpr (std::is_arithmetic_v<T>) {
    return l[0] * a + l[1] * b + l[2] * c;
  } else {
    return T(l[0] * a + l[1] * b + l[2] * c);
  }
}

/// The per-vertex attribute `values` at barycentric coordinates `l` of
/// triangle `t` (indices into `values`).
template <class Values>
auto interpolate(const Values& values, const Tri& t, const Vec3& l) {
  return interpolate(l, values[t[0]], values[t[1]], values[t[2]]);
}

struct FrameMesh {
  std::vector<Vec3> positions;   ///< one per vertex, scene units
  std::vector<Vec3> velocities;  ///< one per vertex, scene units / second
  std::vector<Tri> triangles;    ///< counter-clockwise seen from outside

  std::size_t num_vertices() const { return positions.size(); }
  std::size_t num_faces() const { return triangles.size(); }
  bool empty() const { return triangles.empty(); }
};

struct BBox {
  Vec3 min = Vec3::Constant(0.0);
  Vec3 max = Vec3::Constant(0.0);
  double diagonal() const { return (max - min).norm(); }
};

/// Axis-aligned bounding box of the positions (all zeros for an empty mesh).
BBox bounding_box(const FrameMesh& mesh);
BBox bounding_box(const std::vector<Vec3>& positions);

/// Unnormalised face normal (twice the area times the unit normal).
Vec3 face_area_normal(const FrameMesh& mesh, std::size_t face);

/// Total surface area.
double surface_area(const FrameMesh& mesh);

/// Mean edge length over all triangle edges (0 for an empty mesh).
double mean_edge_length(const FrameMesh& mesh);

/// Area-weighted unit vertex normals (zero vector for isolated vertices).
std::vector<Vec3> vertex_normals(const FrameMesh& mesh);

/// Connected components over shared vertices: component id per triangle,
/// ids 0..count-1 in order of first appearance. Returns the count.
int face_components(const FrameMesh& mesh, std::vector<int>& component_of_face);

}  // namespace fluidtex
