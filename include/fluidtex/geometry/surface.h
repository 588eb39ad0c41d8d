/// @file surface.h
/// @brief Per-frame surface queries (Gagnon et al. 2019, Sec. 5.2): closest
/// point projection onto the frame's triangles (CGAL AABB tree), with the
/// triangle, barycentric coordinates, interpolated normal and velocity, plus
/// the face adjacency and connected components the patch stages need.
///
/// Built once per frame and then only read, so any number of threads may
/// query it at once.
#pragma once

#include <array>
#include <memory>
#include <numeric>
#include <vector>

#include "fluidtex/geometry/mesh.h"

namespace fluidtex {

/// A point on the surface: triangle and barycentric coordinates.
struct SurfacePoint {
  int face = -1;                 ///< triangle index, -1 when invalid
  Vec3 bary = Vec3::Zero();      ///< barycentric coordinates in that triangle
  Vec3 position = Vec3::Zero();  ///< the point itself
  double distance = 0.0;         ///< distance from the query point (projection only)
  bool valid() const { return face >= 0; }
};

class SurfaceIndex {
 public:
  /// Builds the index; `mesh` must outlive it. An empty mesh is allowed (every
  /// query then returns an invalid point).
  explicit SurfaceIndex(const FrameMesh& mesh);
  ~SurfaceIndex();
  SurfaceIndex(SurfaceIndex&&) noexcept;
  SurfaceIndex& operator=(SurfaceIndex&&) noexcept;

  const FrameMesh& mesh() const { return *mesh_; }

  /// Closest point on the surface to `p` (exact, over all triangles).
  SurfacePoint closest_point(const Vec3& p) const;

  /// Faces whose bounding box meets the box [lo, hi], ascending.
  std::vector<int> faces_in_box(const Vec3& lo, const Vec3& hi) const;

  /// The point at `bary` in `face`.
  SurfacePoint at(int face, const Vec3& bary) const;

  /// Unit normal at a surface point: barycentric blend of the area-weighted
  /// vertex normals; the face normal where the blend degenerates or points
  /// behind the face (a folded face, whose vertex normals face the other way).
  Vec3 normal_at(const SurfacePoint& s) const;
  /// Barycentric blend of the vertex velocities.
  Vec3 velocity_at(const SurfacePoint& s) const;

  const std::vector<Vec3>& face_normals() const { return face_normals_; }  ///< unit
  const std::vector<double>& face_areas() const { return face_areas_; }
  /// Total surface area (the face areas summed in face order).
  double area() const { return std::accumulate(face_areas_.begin(), face_areas_.end(), 0.0); }
  const std::vector<Vec3>& vertex_normals() const { return vertex_normals_; }  ///< unit
  /// Per face, the face across each edge (edge k joins corners k and k+1);
  /// -1 on a boundary edge or a non-manifold edge (more than two faces).
  const std::vector<std::array<int, 3>>& face_neighbors() const { return neighbors_; }
  const std::vector<int>& face_component() const { return component_; }
  /// Vertices on an open boundary edge (an edge with a single triangle).
  const std::vector<char>& vertex_on_boundary() const { return vertex_boundary_; }
  /// True when `s` lies on an open boundary of the surface (on a boundary edge
  /// or at a boundary vertex), as a closest-point query beyond the rim of an
  /// open surface does, or within `tolerance` of one (edges and vertices of
  /// its own triangle).
  bool on_boundary(const SurfacePoint& s, double tolerance = 0.0) const;
  /// The closest point to `p` on an open boundary edge (the rim of an open
  /// surface) no farther than `radius`; invalid when there is none. Its
  /// `distance` is the distance from `p`.
  SurfacePoint closest_rim_point(const Vec3& p, double radius) const;
  int num_components() const { return num_components_; }
  const std::vector<double>& component_area() const { return component_area_; }

 private:
  struct Tree;
  const FrameMesh* mesh_;
  std::unique_ptr<Tree> tree_;
  std::vector<Vec3> face_normals_;
  std::vector<double> face_areas_;
  std::vector<Vec3> vertex_normals_;
  std::vector<std::array<int, 3>> neighbors_;
  std::vector<int> component_;
  std::vector<char> vertex_boundary_;
  std::vector<double> component_area_;
  int num_components_ = 0;
};

/// Barycentric coordinates of `p` (assumed in the plane) in triangle (a, b, c),
/// robust to degenerate triangles (falls back to the closest vertex).
Vec3 barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace fluidtex
