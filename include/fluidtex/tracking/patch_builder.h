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

/// Triangles (face indices) of the disk-like selection around `centre`, in
/// the order they were added (the centre's triangle first).
std::vector<int> select_patch_faces(const SurfaceIndex& surface, const SurfaceSample& centre, double select_radius,
                                    double patch_vertex_angle);

/// A patch's selection larger than this many areas of its selection ball
/// (π r², r = (1 + β)·d) is cut to the cube of half-size kSelectionCube × r
/// around its centre (build_patch). The triangles reaching into the ball lie
/// within r + e of its centre, e the input's edge length: about 1.3 balls
/// where e = d/5, at most 4 where e = r: only inputs far coarser than d are
/// cut.
inline constexpr double kMaxSelectionArea = 8.0;
inline constexpr double kSelectionCube = 2.0;

/// Builds the patch of a new disk; `options` must be resolved (radius > 0).
/// The copied selection, cut to a cube where it is far larger than its ball
/// (kMaxSelectionArea), is remeshed (CGAL isotropic remeshing, vertices kept
/// on the surface) to triangles of about `edge_length` (≤ 0: keep the
/// surface's own triangles) before LSCM. Returns nullopt (with the reason in
/// `failure`) when no usable patch can be made, e.g. when the LSCM solve
/// fails. K_t, state and weights are left for the caller.
std::optional<Patch> build_patch(const SurfaceIndex& surface, const SurfaceSample& centre,
                                 const TrackingOptions& options, std::uint32_t id, std::uint64_t seed, int frame,
                                 double edge_length, std::string* failure = nullptr);

/// A patch found too distorted, cut again around its own centre from the
/// current `surface` (build_patch: selection, remeshing, LSCM), keeping its
/// id, fading state, age and texture. Departure from the paper, which fades
/// such a patch out and lets a new disk, with a new texture, replace it: the
/// new uv are turned, and the texture shifted (Patch::texture_offset), to
/// match what the old patch showed, a least-squares fit over the new
/// vertices weighted by both patches' K_S radial terms times the old
/// patch's Q_V there. Each vertex then shows at first only as much as the
/// old patch showed there (Patch::recovery: its Q_V, 0 where it did not
/// cover), rising as a fading-in K_t does. So where the old patch was little
/// distorted the texture stays in place, and where it was crushed or torn
/// (shown faintly, Q_V) the new texture fades in rather than appearing at
/// once. nullopt when no patch can be built or it overlaps too little of
/// what the old one showed to be matched.
std::optional<Patch> recut_patch(const Patch& old, const SurfaceIndex& surface, const TrackingOptions& options,
                                 std::uint64_t seed, int frame, double edge_length);

}  // namespace fluidtex
