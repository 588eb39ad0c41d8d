/// @file patch_builder.h
/// @brief Deformable patch creation (Gagnon et al. 2019, Sec. 5.1): copy the
/// surface triangles around a Poisson disk and flatten them with Least Squares
/// Conformal Maps (Lévy et al. 2002, CGAL's LSCM_parameterizer_3).
///
/// Selection grows a region from the disk's triangle in order of distance to
/// the centre, taking a triangle when it reaches within (1 + β)·d of the
/// centre (a corner or its centroid) and its normal passes the plane test
/// N_T·N > pva.
/// Departure from the paper, which only says "the polygons surrounding the
/// disk": the growth keeps the region a topological disk at every step
/// (disk_region.h), so LSCM always applies.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "fluidtex/tracking/options.h"
#include "fluidtex/tracking/patch.h"

namespace fluidtex {

/// Triangles (face indices) of the disk-like selection around `center`, in
/// the order they were added (the centre's triangle first).
std::vector<int> select_patch_faces(const SurfaceIndex& surface, const SurfaceSample& center, double select_radius,
                                    double patch_vertex_angle);

/// Builds the patch of a new disk; `options` must be resolved (radius > 0).
/// The copied selection is remeshed (CGAL isotropic remeshing, vertices kept
/// on the surface) to triangles of about `edge_length` (≤ 0: keep the
/// surface's own triangles) before LSCM. Returns nullopt (with the reason in
/// `failure`) when no usable patch can be made, e.g. when the LSCM solve
/// fails. K_t, state and weights are left for the caller.
std::optional<Patch> build_patch(const SurfaceIndex& surface, const SurfaceSample& center,
                                 const TrackingOptions& options, std::uint32_t id, std::uint64_t seed, int frame,
                                 double edge_length, std::string* failure = nullptr);

}  // namespace fluidtex
