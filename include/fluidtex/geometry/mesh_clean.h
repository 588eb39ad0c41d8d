/// @file mesh_clean.h
/// @brief Minimal repair of a reconstructed surface: merge coincident
/// vertices, drop degenerate and duplicate triangles, drop unreferenced
/// vertices, and count (not repair) non-manifold edges. Velocities of merged
/// vertices are averaged.
#pragma once

#include <cstddef>
#include <string>

#include "fluidtex/geometry/mesh.h"

namespace fluidtex {

struct CleanOptions {
  /// Vertices closer than this fraction of the bounding-box diagonal are merged
  /// (greedily, in index order: each vertex joins the lowest-index earlier
  /// representative within reach). 0 merges only bit-identical positions.
  double merge_tolerance = 1e-9;
  /// Triangles whose area is at most this × diagonal² are degenerate (the
  /// default is about the area float rounding can leave on a flat triangle).
  double degenerate_area = 1e-14;
};

struct CleanReport {
  std::size_t merged_vertices = 0;        ///< vertices merged into another
  std::size_t degenerate_faces = 0;       ///< zero-area or repeated-index triangles dropped
  std::size_t duplicate_faces = 0;        ///< same three vertices as an earlier triangle
  std::size_t unreferenced_vertices = 0;  ///< vertices used by no triangle, dropped
  std::size_t nonmanifold_edges = 0;      ///< edges with more than two triangles (kept)
  std::size_t boundary_edges = 0;         ///< edges with one triangle
  int components = 0;                     ///< connected components after cleaning
  bool changed() const { return merged_vertices + degenerate_faces + duplicate_faces + unreferenced_vertices > 0; }
  /// One line: "clean" when nothing was changed and the mesh is one closed
  /// manifold piece, else e.g. "merged 3 vertices, dropped 2 degenerate and
  /// 1 duplicate faces, 0 unreferenced vertices; 4 non-manifold edges,
  /// 12 boundary edges, 2 components".
  std::string summary() const;
};

/// Cleans `mesh` in place and returns what was done. Kept vertices and
/// triangles keep their relative order; merged vertices take the position of
/// their lowest-index member and the mean velocity of all members.
CleanReport clean_mesh(FrameMesh& mesh, const CleanOptions& options = {});

}  // namespace fluidtex
