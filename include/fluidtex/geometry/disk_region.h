/// @file disk_region.h
/// @brief Growing a region of triangles that stays a topological disk, in
/// order of a priority, over the faces a predicate accepts. Used to cut
/// deformable patches (Gagnon et al. 2019, Sec. 5.1) and atlas charts: both
/// are flattened by LSCM, which needs a disk.
///
/// A triangle joins only along exactly one boundary edge with a new corner,
/// or along two consecutive boundary edges; it never joins across an edge
/// already inside the region, against the region's orientation, or across a
/// non-manifold edge. Every intermediate region is therefore a disk, and holes
/// or handles of the surface are never closed over.
#pragma once

#include <functional>
#include <vector>

#include "fluidtex/geometry/surface.h"

namespace fluidtex {

struct DiskRegionOptions {
  /// May face f join? (Checked once per face.)
  std::function<bool(int face)> accept;
  /// Faces are tried in increasing priority (ties by face index).
  std::function<double(int face)> priority;
  /// Stop when the region has this many faces (0 = no limit).
  std::size_t max_faces = 0;
};

/// Grows from `seed` (always included); returns the faces in the order they
/// joined.
std::vector<int> grow_disk_region(const SurfaceIndex& surface, int seed, const DiskRegionOptions& options);

}  // namespace fluidtex
