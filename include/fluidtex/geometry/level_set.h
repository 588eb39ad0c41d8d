/// @file level_set.h
/// @brief Meshing an OpenVDB level set into a frame surface: volumeToMesh at
/// an iso value, quads split along their shorter diagonal, triangles
/// oriented out of the liquid (the level set is negative inside).
#pragma once

#include <openvdb/openvdb.h>

#include "fluidtex/geometry/mesh.h"

namespace fluidtex {

/// Calls openvdb::initialize() once per process (thread-safe); every user of
/// OpenVDB's grid registry or file I/O goes through it.
void initialize_openvdb();

/// The iso surface of `grid` at `iso` (world units, like the level set's
/// values) with OpenVDB's `adaptivity` in [0, 1] (0: one vertex per crossed
/// voxel edge; towards 1: fewer, larger polygons where the surface is flat),
/// in world space (the grid's transform applied). Velocities are zero.
FrameMesh mesh_level_set(const openvdb::FloatGrid& grid, double iso = 0.0, double adaptivity = 0.0);

}  // namespace fluidtex
