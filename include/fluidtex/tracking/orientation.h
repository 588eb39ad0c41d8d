/// @file orientation.h
/// @brief How a new patch shows its exemplar, chosen once when it is born:
/// the turn of its uv about its centre, and which part of the exemplar it
/// shows (its anchor, apart from its neighbours').
///
/// The turn (Praun, Finkelstein and
/// Hoppe 2000, "Lapped Textures": patches oriented by a tangent direction
/// field). LSCM (parameterization.h) leaves a chart at an arbitrary
/// rotation, so without a turn every patch shows the exemplar at its own
/// angle: a directional or lit exemplar reads as fur, bricks as a heap.
///
/// Departure from the paper, which leaves the chart as LSCM gives it
/// (Orientation::Random keeps that). With Orientation::Field a patch's u
/// axis agrees with the u axes of the live patches it overlaps, carried to
/// it through their own charts and averaged with their weights; where it
/// overlaps none (the first frame, a new droplet) it follows a world axis
/// projected onto the surface. Once born, a patch keeps its uv: it turns
/// with the liquid, and so the field the next births agree with turns with
/// it. A recut (recut_patch) keeps the orientation of the patch it replaces.
#pragma once

#include <cstdint>
#include <vector>

#include "fluidtex/geometry/surface.h"
#include "fluidtex/tracking/options.h"
#include "fluidtex/tracking/patch.h"
#include "fluidtex/tracking/patch_coverage.h"

namespace fluidtex {

/// A patch moving at least this many disk radii a frame (its disk's mean
/// surface velocity) is fast enough for Orientation::Flow to follow its
/// velocity; slower ones take the field.
inline constexpr double kFlowOrientationMotion = 0.05;

/// ∂x/∂u on triangle `t` of `patch`: the 3D vector by which a point of the
/// triangle moves per unit of u (tangent to the triangle; zero when its uv
/// are degenerate).
Vec3 u_axis(const Patch& patch, const Tri& t);

/// The uv displacement of `patch`'s triangle `t` that moves a point by the
/// 3D vector `a` (its component out of the triangle's plane dropped): the
/// inverse of the triangle's affine map. Zero for a degenerate triangle.
Vec2 uv_of(const Patch& patch, const Tri& t, const Vec3& a);

/// `axis` projected onto the plane of normal `n`, or the next axis
/// (x → y → z → x) where the normal lies within 30° of it; unit length.
Vec3 world_direction(Axis axis, const Vec3& n);

/// Turns every uv of `patch` by `angle` radians about its centre (the
/// origin), counter-clockwise: the exemplar it shows turns by −angle.
void turn_uv(Patch& patch, double angle);

/// What a new patch's turn is chosen from: the live patches (those of the
/// distribution before this batch of births) with their coverage index, or
/// none on an empty distribution; the step's frame time for Flow.
struct OrientationContext {
  const SurfaceIndex& surface;
  const std::vector<Patch>& live;
  const PatchCoverage* coverage = nullptr;  ///< over `live`; null when `live` is empty
  double dt = 0.0;                          ///< seconds per frame (Flow)
};

/// Patches whose centres lie closer than this many disk radii are
/// neighbours (their disks overlap) for separate_anchors.
inline constexpr double kNeighbourSpan = 2.0;
/// The least distance, in exemplar tiles on the torus the tiled exemplar
/// makes, between the anchors of two neighbouring patches.
inline constexpr double kAnchorSeparation = 0.25;
/// Anchors drawn for a new patch before the farthest is taken.
inline constexpr int kAnchorDraws = 8;

/// Distance of two anchors on the torus of the tiled exemplar (tiles).
double anchor_distance(const Vec2& a, const Vec2& b);

/// Gives each of `fresh` (a batch of new patches, in order) an anchor apart
/// from its neighbours' (kNeighbourSpan, same side of the surface: normals
/// at less than 90°) among `live` and the earlier patches of the batch, so
/// that neighbours never show the same part of the exemplar and the patch
/// spacing does not show as a repeat: the first of kAnchorDraws anchors
/// drawn from (seed, patch id) at least kAnchorSeparation from all of
/// theirs, else the draw farthest from the nearest of them. The first draw
/// is the anchor build_patch gives, so a patch without neighbours keeps it.
/// A recut patch's texture offset is not part of the comparison: anchors
/// are in tiles, the offset in scene units (the tile's span is the job's).
void separate_anchors(const std::vector<Patch*>& fresh, const std::vector<Patch>& live, double d, std::uint64_t seed);

/// The angle by which turn_uv turns a new patch so that its u axis follows
/// options.orientation (0 for Random): per triangle of the patch inside its
/// disk, the target direction in the patch's uv, averaged as unit vectors
/// weighted by the triangle's area, its K_S radial term and, for Field, the
/// weight of each live patch over the triangle's centroid. Deterministic:
/// sums run in triangle and patch order.
double orientation_angle(const Patch& fresh, const OrientationContext& context, const TrackingOptions& options);

}  // namespace fluidtex
