/// @file vdb_io.h
/// @brief OpenVDB frames: a narrow-band level set (the liquid surface) and a
/// vector grid (its velocity), as Houdini, Blender's Mantaflow cache,
/// EmberGen and most solvers write them.
///
/// Reading meshes the level set with volumeToMesh (geometry/level_set.h) and
/// samples the velocity grid at the vertices in world space, through each
/// grid's own transform: trilinear for a collocated grid, OpenVDB's staggered
/// sampler for a MAC grid (grid class "staggered": component k of voxel ijk
/// lives on the face at ijk − ½ e_k). Only the grids named or chosen are read:
/// a cache's other grids (density, flags, particle grids whose attribute
/// types a stock OpenVDB cannot load) are never touched. Velocity values are
/// taken as world-space vectors in scene units per second.
#pragma once

#include <string>
#include <vector>

#include "fluidtex/geometry/mesh.h"

namespace fluidtex {

struct VdbReadOptions {
  /// Level-set grid; empty: the first grid (by name) whose class is level
  /// set, else a float grid named `surface` or `phi`.
  std::string surface;
  /// Velocity grid; empty: the first of `vel`, `velocity`, `v` present.
  std::string velocity;
  double iso = 0.0;         ///< iso value of the surface, in the level set's units (world)
  double adaptivity = 0.0;  ///< volumeToMesh adaptivity in [0, 1]
};

/// The names of the velocity grids looked for when none is named.
const std::vector<std::string>& default_vdb_velocity_names();

/// One frame from a .vdb file: the level set meshed (outward triangles) with
/// velocities sampled from the velocity grid (zero when `require_velocities`
/// is false and the file has none). InputError naming the file for: a file
/// OpenVDB cannot open or read, no level set (listing the file's grids), a
/// named grid that is missing, a surface grid that is not float or is a fog
/// volume, a velocity grid that does not hold vectors, a velocity grid with
/// no active value near the surface, NaN/Inf velocities, an empty surface.
FrameMesh read_vdb_frame(const std::string& path, const VdbReadOptions& options, bool require_velocities);

/// Samples the velocity grid of the .vdb file `path` (options.velocity or a
/// default name) at `positions` (world space), for meshes whose velocities
/// come from a VDB cache (`--velocity-vdb`). Same errors as read_vdb_frame.
std::vector<Vec3> read_vdb_velocities(const std::string& path, const VdbReadOptions& options,
                                      const std::vector<Vec3>& positions);

struct VdbWriteOptions {
  double voxel_size = 0.02;  ///< world units
  double half_width = 3.0;   ///< narrow band on each side, in voxels
  bool staggered = false;    ///< write the velocity as a MAC grid
  std::string surface = "surface";
  std::string velocity = "vel";
};

/// Writes `mesh` (closed, outward-oriented) as a level set (meshToVolume) and
/// its velocity as a vector grid over the level set's narrow band, each
/// voxel (or, staggered, each face) taking the velocity of its closest
/// surface point. Written atomically. InternalError if the mesh is not
/// closed enough to have an inside.
void write_vdb_frame(const std::string& path, const FrameMesh& mesh, const VdbWriteOptions& options);

}  // namespace fluidtex
