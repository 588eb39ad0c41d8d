/// @file parameterization.h
/// @brief Flattening and remeshing of small disk-shaped triangle meshes with
/// CGAL (kept behind this header): Least Squares Conformal Maps (Lévy et al.
/// 2002, `Surface_mesh_parameterization::LSCM_parameterizer_3`) and isotropic
/// remeshing (`Polygon_mesh_processing::isotropic_remeshing`).
#pragma once

#include <string>
#include <vector>

#include "fluidtex/geometry/mesh.h"

namespace fluidtex {

/// A small indexed triangle mesh.
struct DiskMesh {
  std::vector<Vec3> positions;
  std::vector<Tri> triangles;
};

/// The faces `faces` of `mesh` as a compact DiskMesh (vertices renumbered in
/// order of first use).
DiskMesh extract_faces(const FrameMesh& mesh, const std::vector<int>& faces);

/// LSCM of a topological disk, made metric: uv area equals 3D area and the
/// orientation is kept (counter-clockwise triangles stay counter-clockwise).
/// CGAL pins two border vertices at arbitrary positions, so the raw result is
/// rescaled. Returns false (reason in `failure`) when the mesh is not a
/// manifold disk or the solve fails.
bool flatten_lscm(const DiskMesh& mesh, std::vector<Vec2>& uvs, std::string* failure = nullptr);

/// Isotropic remeshing of a disk to edges of about `edge_length`; vertices
/// stay on the input surface, and border edges are split but never collapsed,
/// so the border keeps its exact shape (the remeshed disk covers exactly what
/// the input covered). Returns false when the input is not a manifold mesh
/// (the input is then left as is).
bool remesh_disk(DiskMesh& mesh, double edge_length, int iterations = 3);

}  // namespace fluidtex
