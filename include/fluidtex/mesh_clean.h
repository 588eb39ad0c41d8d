/// @file mesh_clean.h
/// @brief Minimal repair of a reconstructed surface: merge coincident
/// vertices, drop degenerate and duplicate triangles, drop unreferenced
/// vertices, and count (not repair) non-manifold edges. Velocities of merged
/// vertices are averaged.
#pragma once

#include <cstddef>
#include <string>

#include "fluidtex/mesh.h"

namespace fluidtex {

struct CleanOptions {
  /// Vertices closer than this fraction of the bounding-box diagonal are merged.
  double merge_tolerance = 1e-9;
  /// Triangles whose area is below (this × diagonal)² are degenerate.
  double degenerate_area = 1e-14;
};

struct CleanReport {
  std::size_t merged_vertices = 0;       ///< vertices merged into another
  std::size_t degenerate_faces = 0;      ///< zero-area or repeated-index triangles dropped
  std::size_t duplicate_faces = 0;       ///< same three vertices as an earlier triangle
  std::size_t unreferenced_vertices = 0; ///< vertices used by no triangle, dropped
  std::size_t nonmanifold_edges = 0;     ///< edges with more than two triangles (kept)
  std::size_t boundary_edges = 0;        ///< edges with one triangle
  int components = 0;                    ///< connected components after cleaning
  bool changed() const {
    return merged_vertices + degenerate_faces + duplicate_faces + unreferenced_vertices > 0;
  }
  /// One line, e.g. "merged 3 vertices, dropped 2 degenerate faces".
  std::string summary() const;
};

/// Cleans `mesh` in place and returns what was done.
CleanReport clean_mesh(FrameMesh& mesh, const CleanOptions& options = {});

}  // namespace fluidtex
