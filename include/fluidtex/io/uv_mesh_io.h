/// @file uv_mesh_io.h
/// @brief The per-frame UV mesh (geometry/uv_mesh.h) written (OBJ, PLY)
/// and read back (for eval, compare and preview).
///
/// Both writers pass the frame through unchanged (non-manifold and
/// unreferenced vertices included), write numbers as 32-bit floats in the
/// shortest text that round-trips (locale-independent), give byte-identical
/// files for identical meshes, and write atomically. Index arrays out of
/// range, mismatched array sizes or non-finite values are an InternalError
/// (nothing is written). `normals` may be empty (no `vn` / zero normals) and
/// `uv_triangles` may be empty (no `vt` / zero uvs).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "fluidtex/geometry/uv_mesh.h"

namespace fluidtex {

/// The images an OBJ's material names: the colour atlas (map_Kd), and when
/// written a height atlas (disp, and bump with `-bm bump_height`, the scene
/// height of white above black) and a tangent-space normal atlas (norm).
struct MaterialMaps {
  std::string color;
  std::string displacement;
  std::string normal;
  double bump_height = 1.0;
  MaterialMaps() = default;
  MaterialMaps(std::string color_image) : color(std::move(color_image)) {}  // NOLINT: a string names the colour
  MaterialMaps(const char* color_image) : color(color_image) {}             // NOLINT
};

/// Writes a Wavefront OBJ (`v`, `vt`, `vn`, `f v/vt/vn`, 1-based), atomically.
/// With `maps.color` non-empty, first writes a sibling `<stem>.mtl` (material
/// "fluidtex_atlas") naming the maps, and adds `mtllib`/`usemtl` lines.
/// A relative image path is written as given (it should be relative to the
/// OBJ's folder, usually the atlas's file name); an absolute one is made
/// relative to the OBJ's folder.
void write_uv_mesh_obj(const std::string& path, const UVMesh& mesh, const MaterialMaps& maps = {});

/// Writes a binary little-endian PLY with per-vertex `float x y z nx ny nz u v`
/// (then `vx vy vz` when the mesh has velocities, for a renderer's
/// deformation motion blur) and `list uchar int vertex_indices`, atomically. Vertices are split: one
/// output vertex per distinct (vertex, uv index) pair used by a corner, in
/// order of (vertex, uv index); unreferenced vertices are kept with uv (0,0).
void write_uv_mesh_ply(const std::string& path, const UVMesh& mesh);

/// Picks the writer from the extension (.obj or .ply); InputError otherwise.
/// `maps`: the OBJ's material textures (write_uv_mesh_obj); PLY has none.
void write_uv_mesh(const std::string& path, const UVMesh& mesh, const MaterialMaps& maps = {});

/// Reads a UV mesh written by write_uv_mesh_obj (v, vt, vn, f v/vt/vn) through
/// OpenMesh; InputError when the file is missing or malformed.
UVMesh read_uv_mesh_obj(const std::string& path);

/// Reads a UV mesh written by write_uv_mesh_ply (binary little-endian, vertex
/// properties x y z u v, optionally nx ny nz and vx vy vz, in any order and of
/// any numeric type; faces one integer list). Its vertices are split at
/// seams, so `uvs` is per vertex and `uv_triangles` equals `triangles`.
/// InputError naming the file for anything else: another format, a missing
/// property, a truncated body, an index out of range, a non-finite value.
UVMesh read_uv_mesh_ply(const std::string& path);

/// Picks the reader from the extension (.obj or .ply); InputError otherwise.
UVMesh read_uv_mesh(const std::string& path);

}  // namespace fluidtex
