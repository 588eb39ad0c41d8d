/// @file uv_mesh.h
/// @brief The per-frame UV mesh: the frame's surface with atlas coordinates.
/// Seams carry per-corner UVs: a vertex on a chart border has one uv per
/// chart. Files are io/uv_mesh_io.h's.
#pragma once

#include <vector>

#include "fluidtex/geometry/mesh.h"

namespace fluidtex {

struct UVMesh {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;      ///< per vertex (same indexing as positions)
  std::vector<Tri> triangles;     ///< into positions
  std::vector<Vec2> uvs;          ///< atlas coordinates in [0,1]², v up (OBJ convention)
  std::vector<Tri> uv_triangles;  ///< per corner, into uvs; same count as triangles
  std::vector<Vec3> velocities;   ///< per vertex, scene units per second (the input's); empty: none
};

}  // namespace fluidtex
