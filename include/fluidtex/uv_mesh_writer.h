/// @file uv_mesh_writer.h
/// @brief The per-frame UV mesh: the frame's surface with atlas coordinates.
/// Seams carry per-corner UVs: a vertex on a chart border has one uv per chart.
#pragma once

#include <string>
#include <vector>

#include "fluidtex/mesh.h"

namespace fluidtex {

struct UVMesh {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;     ///< per vertex (same indexing as positions)
  std::vector<Tri> triangles;    ///< into positions
  std::vector<Vec2> uvs;         ///< atlas coordinates in [0,1]², v up (OBJ convention)
  std::vector<Tri> uv_triangles; ///< per corner, into uvs; same count as triangles
};

/// Writes a Wavefront OBJ (`v`, `vt`, `vn`, `f v/vt/vn`), atomically. With
/// `mtl_image` non-empty, also writes a sibling `.mtl` naming it as map_Kd.
void write_uv_mesh_obj(const std::string& path, const UVMesh& mesh,
                       const std::string& mtl_image = {});

/// Writes a binary little-endian PLY with per-vertex `x y z nx ny nz u v`
/// after splitting every vertex that has more than one uv, atomically.
void write_uv_mesh_ply(const std::string& path, const UVMesh& mesh);

/// Picks the writer from the extension (.obj or .ply); InputError otherwise.
void write_uv_mesh(const std::string& path, const UVMesh& mesh);

}  // namespace fluidtex
