/// @file mesh_io.h
/// @brief Reading one frame of a mesh sequence: PLY (ASCII, binary little and
/// big endian) with per-vertex velocities, OBJ (positions only, for
/// `--velocity-from-positions` or `--velocity-vdb`), or an OpenVDB level set
/// with a velocity grid (vdb_io.h). Parsing is OpenMesh's; this module validates
/// the file first (header, property types, expected size of binary bodies) so
/// that every problem becomes a one-line InputError naming the file.
/// PLY values keep their declared precision (float or double); OBJ positions
/// pass through OpenMesh's float reader. Any PLY list count/index integer
/// types are accepted, the face list may be named vertex_indices or
/// vertex_index, and extra elements/properties are ignored.
#pragma once

#include <optional>
#include <string>

#include "fluidtex/geometry/mesh.h"
#include "fluidtex/geometry/mesh_clean.h"
#include "fluidtex/io/vdb_io.h"

namespace fluidtex {

/// Most corners a polygon may have (ear clipping is cubic in it; liquid
/// meshes have triangles and quads).
inline constexpr int kMaxPolygonCorners = 256;

struct ReadOptions {
  /// Names of the velocity triple, e.g. "vel_x,vel_y,vel_z" or a prefix "vel"
  /// meaning vel_x/vel_y/vel_z or else velx/vely/velz. Empty: auto-detect `vx vy vz`,
  /// `velocity_x velocity_y velocity_z`, `v_x v_y v_z` (first complete triple wins).
  std::string velocity_attr;
  /// When false, velocities are not required (OBJ input, or velocities to be
  /// derived from positions); `velocities` is then filled with zeros.
  bool require_velocities = true;
  /// Clean the mesh after reading (see mesh_clean.h).
  bool clean = true;
  CleanOptions clean_options;
  /// How to read .vdb frames (level set and velocity grids).
  VdbReadOptions vdb;
};

/// Reads a frame. Polygons are triangulated (ear clipping in the polygon's
/// plane, so simple concave polygons keep their orientation). Throws InputError for a missing
/// or unreadable file, unknown format, truncated body, wrong property types
/// (velocity properties must be float or double), missing velocities (when
/// required), NaN/Inf in positions or velocities, out-of-range indices, and
/// an empty mesh (no triangle left after cleaning). `report` (optional)
/// receives what cleaning did; faces with fewer than three corners count as
/// degenerate. Safe to call from several threads (the OpenMesh parse itself
/// is serialised: its readers are process-wide singletons).
FrameMesh read_frame(const std::string& path, const ReadOptions& options = {}, CleanReport* report = nullptr);

/// The frame rate the header of the PLY file at `path` states in a comment
/// (`comment ... fps=24`, or `fps 24` as fluidtex's Blender exporter writes
/// it); nullopt for other formats, a header that states none, or a file that
/// cannot be read as PLY (read_frame says why).
std::optional<double> read_stated_fps(const std::string& path);

/// clean_mesh() on the frame read from `path`; InputError naming the file
/// when no face is left.
CleanReport clean_frame(const std::string& path, FrameMesh& mesh, const CleanOptions& options = {});

}  // namespace fluidtex
