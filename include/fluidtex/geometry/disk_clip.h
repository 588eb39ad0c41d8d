/// @file disk_clip.h
/// @brief A patch's selection cut down to a box around its disk, so that
/// the work of a patch follows the disk's size, not the input's triangles'.
#pragma once

#include "fluidtex/geometry/parameterization.h"

namespace fluidtex {

/// Clips `disk` (a triangle mesh, typically a topological disk) to the
/// axis-aligned cube of half-size `half` around `centre` (CGAL's
/// Polygon_mesh_processing::clip, the surface only) and keeps the piece
/// whose triangle lies nearest to `centre`. Triangles that lie wholly inside
/// keep their vertices; crossing ones are cut along the cube's faces.
/// Returns false, leaving `disk` as it is, when no vertex lies outside the
/// cube (nothing to cut) or when the mesh is not a manifold CGAL can clip.
bool clip_disk_to_cube(DiskMesh& disk, const Vec3& centre, double half);

}  // namespace fluidtex
