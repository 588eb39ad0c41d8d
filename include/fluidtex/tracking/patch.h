/// @file patch.h
/// @brief A deformable patch (Gagnon et al. 2019, Sec. 5): a copy of the
/// surface triangles around a Poisson disk, flattened once (LSCM) so that each
/// vertex keeps its texture coordinate while its 3D position is advected.
#pragma once

#include <cstdint>
#include <vector>

#include "fluidtex/geometry/distortion.h"
#include "fluidtex/geometry/mesh.h"
#include "fluidtex/geometry/surface.h"
#include "fluidtex/tracking/fading.h"
#include "fluidtex/tracking/poisson.h"

namespace fluidtex {

struct Patch {
  std::uint32_t id = 0;  ///< unique, increasing with creation
  DiskState state = DiskState::FadingIn;
  double kt = 0.0;  ///< temporal weight K_t ∈ [0, 1]
  int created_frame = 0;
  int close_frames = 0;  ///< frames in a row it has been within the kill distance of an older patch
  /// The surface change around its centre (ln area ratio per frame,
  /// surface_change.h) summed over the last frames with weights decaying by
  /// 1 − 1/kill-frames a frame: about the area lost over the last
  /// kill-frames frames (Sink::Fade).
  double sunk = 0.0;
  int flagged_frame = -1;                 ///< frame it started fading out (t_k), −1 if not
  int recut_frame = -1;                   ///< last frame it was cut again in place (recut_patch), −1 if never
  RetireCause cause = RetireCause::None;  ///< why it is fading out (None while it is not)
  int density = 0;                        ///< ρ at the last update
  double motion = 0.0;                    ///< how far the centre moved in the last step, in units of d

  SurfaceSample centre;        ///< the Poisson disk: centre on the current surface, normal
  Vec2 anchor = Vec2::Zero();  ///< exemplar position of the centre, in tiles ([0,1)²)
  /// Added to every uv at exemplar lookup (metric, 0 when built): a recut
  /// patch (recut_patch) keeps showing the texture its predecessor showed,
  /// while its uv keep the centre at the origin.
  Vec2 texture_offset = Vec2::Zero();

  // The patch mesh. uv is metric (scene units, centre at the origin, uv area
  // equals the 3D area at creation); synthesis maps it to the exemplar.
  std::vector<Vec3> positions;            ///< current 3D positions (on the surface)
  std::vector<SurfacePoint> projections;  ///< where each vertex lies on the current surface
  std::vector<Vec2> uvs;
  std::vector<Tri> triangles;
  std::vector<RestTriangle> rest;    ///< per triangle: shape at creation (distortion metric)
  std::vector<std::uint8_t> border;  ///< d_V = 0 when 1 (vertex on the patch boundary)
  std::vector<float> quality;        ///< Q_V per vertex
  /// Per vertex after a recut (recut_patch): the share of its weight it
  /// shows, starting at what the patch showed there before the recut and
  /// rising to 1 as a fading-in K_t does; empty when every vertex shows it all.
  std::vector<float> recovery;
  std::vector<float> weight;  ///< w_V = K_S·K_t per vertex (Eq. 2)

  double max_distortion = 1.0;  ///< max D_T over the triangles at the last update
  /// Σ over the triangles at creation of seen_weight(): what the whole disk
  /// weighs in the patch-scale distortion test (DistortionTest::Patch).
  double disk_weight = 0.0;

  std::size_t num_vertices() const { return positions.size(); }
  bool empty() const { return triangles.empty(); }
};

/// Q_V of vertex `v` as its weight shows it: times its recovery after a recut.
inline double shown_quality(const Patch& patch, std::size_t v) {
  return patch.recovery.empty() ? patch.quality[v] : patch.quality[v] * patch.recovery[v];
}

/// How much triangle `t` of `patch` shows: its rest area times K_S's radial
/// term (1 − |uv|/d, at its uv centroid), 0 outside the disk.
double seen_weight(const Patch& patch, std::size_t t, double radius);

/// Per triangle, bit k is set when its edge from corner k to corner k+1 is
/// used by no other triangle (a boundary edge of the triangle list).
std::vector<std::uint8_t> boundary_edge_bits(const std::vector<Tri>& triangles);

/// Recomputes `border` (d_V = 0): vertices on an edge used by exactly one
/// patch triangle, except edges lying along an open boundary of `surface`
/// itself (both ends projected on the rim). Departure from the paper: d_V
/// exists to fade a patch out where another takes over; along the rim of an
/// open surface (the 2D scenes) nothing takes over, and zeroing the weight
/// there would leave the rim triangles uncovered.
void update_border(Patch& patch, const SurfaceIndex& surface);

/// Removes the vertices where `keep` is 0 with every triangle using them, then
/// any vertex no triangle uses, keeping the order of the rest.
void remove_vertices(Patch& patch, const std::vector<std::uint8_t>& keep, const SurfaceIndex& surface);

/// Removes the triangles where `keep` is 0, then the vertices no triangle
/// uses, keeping the order of the rest.
void remove_triangles(Patch& patch, const std::vector<std::uint8_t>& keep, const SurfaceIndex& surface);

}  // namespace fluidtex
