/// @file advection.h
/// @brief Patch advection and projection (Gagnon et al. 2019, Sec. 5.2).
/// The distortion a patch then shows is patch_distortion.h's, its vertex
/// weights weights.h's.
///
/// Every vertex (and the disk centre) moves by the surface velocity at its
/// projection on the previous frame times dt, then snaps to the closest point
/// of the new frame's surface; a vertex farther than mpt from it is removed
/// with its triangles, and a centre farther than mpt kills its patch.
#pragma once

#include "fluidtex/tracking/options.h"
#include "fluidtex/tracking/patch.h"
#include "fluidtex/tracking/weights.h"
#include "fluidtex/util/enum_names.h"

namespace fluidtex {

/// Raw values are stored in state files: append, never reorder.
enum class Advection {
  /// x + v_f(x)·dt (the default): solvers store with frame f the velocity
  /// that carries its surface to frame f+1, and this is that motion. On the
  /// real caches it lowers the warping ratio (the texture's change along
  /// v_f·dt over its change in place) by a quarter against Heun
  /// (docs/tracking.md, "Advection timing").
  Euler,
  /// x + ½(v_f(x) + v_{f+1}(x̃))·dt, x̃ the Euler guess projected onto frame
  /// f+1's surface: second order for velocities sampled at the frame's
  /// instant (analytic flows). On a rigid rotation of the real drop mesh at
  /// 1 rad/s, Euler drifts 5.8e-4 m per frame at the box corners and the
  /// patches reach D = 1.32 in 8 frames; Heun drifts 8e-6 m and stays at
  /// D = 1.005. On solver output v_{f+1} belongs to the next step and runs
  /// ahead of accelerating liquid.
  Heun,
};

inline constexpr EnumName<Advection> kAdvectionNames[] = {{Advection::Euler, "euler"}, {Advection::Heun, "heun"}};
constexpr const auto& enum_names(Advection) { return kAdvectionNames; }
inline const char* to_string(Advection a) { return enum_name(a); }

/// How a patch's vertices follow the flow (Sec. 5.2).
enum class PatchMotion {
  /// Every vertex is advected on its own and projected (the paper). On real
  /// solver output the per-vertex velocities and the surface re-meshed every
  /// frame make neighbouring vertices wander apart, and the patch is judged
  /// distorted within a few frames.
  Vertex,
  /// The default (departure from the paper): the advected vertex positions
  /// are fitted by one smooth map of the patch's rest coordinates (a cubic
  /// in uv, least squares weighted as K_S weighs the texture), and that map,
  /// evaluated at every vertex and at the centre, is projected onto the new
  /// surface. The patch follows the flow's translation, rotation, stretch,
  /// shear and bending at its own scale; noise at the scale of its triangles
  /// cannot crush or flip them, and does not accumulate from frame to frame.
  Smooth,
};
inline constexpr EnumName<PatchMotion> kPatchMotionNames[] = {{PatchMotion::Smooth, "smooth"},
                                                              {PatchMotion::Vertex, "vertex"}};
constexpr const auto& enum_names(PatchMotion) { return kPatchMotionNames; }
inline const char* to_string(PatchMotion m) { return enum_name(m); }

/// A smooth map of a patch's rest (uv) coordinates to 3D: a cubic
/// polynomial in u/d, v/d (a quadratic or an affine one when the vertices
/// cannot determine more).
struct SmoothMap {
  static constexpr int kTerms = 10;  ///< monomials up to degree 3
  Eigen::Matrix<double, kTerms, 3> coefficients = Eigen::Matrix<double, kTerms, 3>::Zero();
  double scale = 1.0;  ///< d: uv is divided by it
  Vec3 operator()(const Vec2& uv) const;
};

/// Least-squares fit of `targets` (one per patch vertex) as a smooth map of
/// the vertices' uv, each weighted by its rest area (a third of its
/// triangles' uv area) times the radial term of its texture weight
/// (radial_weight): the map follows the flow where the texture shows, the
/// margin beyond d holding it there only as faintly as it is seen.
/// False when even an affine map is undetermined (fewer than three vertices
/// with area, or all on a line).
bool fit_smooth_map(const Patch& patch, const std::vector<Vec3>& targets, const TrackingOptions& options,
                    SmoothMap& map);

enum class AdvectResult {
  Kept,        ///< every vertex followed the surface, or only vertices outside the disk were lost
  Damaged,     ///< a vertex inside the disk (|uv| < d, where K_S > 0) was removed
  CentreLost,  ///< the centre left the surface (beyond projection_tolerance): the patch is lost
  Emptied,     ///< no triangle is left: the patch is lost
  /// --distorted recut only: the centre missed the surface (beyond mpt) but
  /// more than half of the vertices stayed on it; the centre is moved to
  /// the surface point nearest its advected position, and the tracker recuts
  /// the patch there (or fades it out) instead of losing it.
  CentreMoved,
  /// The centre left through an open rim (an outflow: the surface ends
  /// there and the liquid moves on past it). It is put on the rim, the
  /// vertices as ever, and the tracker fades the patch out there: its
  /// liquid is leaving, and until it has, the patch still covers what is
  /// left of it.
  LeftThroughRim,
};
inline bool is_lost(AdvectResult r) { return r == AdvectResult::CentreLost || r == AdvectResult::Emptied; }

/// Advects `patch` from `previous` to `next`. A Damaged patch no longer
/// covers its disk: the tracker fades it out as distorted so that the Poisson
/// update replaces it (the paper: vertex removal "allows for the introduction
/// of new patches"). On an open surface, a vertex or centre on the rim that
/// the rim carried along stays on it (docs/method.md, "open rims").
AdvectResult advect_patch(Patch& patch, const SurfaceIndex& previous, const SurfaceIndex& next, double dt,
                          const TrackingOptions& options, Advection scheme, PatchMotion motion = PatchMotion::Smooth);

/// How far from `next` a point advected from `from` (surface normal
/// `normal` there) to `target` may land and still be on the liquid: mpt plus
/// κ (--projection-slack) times the displacement's component along the
/// normal. The solver's velocity predicts a fast sheet's motion along its
/// normal to within a fraction of that motion; the distance beyond the new
/// surface is that error, not a sign that the point left the liquid.
double projection_tolerance(const SurfacePoint& from, const Vec3& normal, const Vec3& target,
                            const TrackingOptions& options);

/// Where one surface point is carried in dt (before projection onto `next`);
/// Heun's second velocity is read at the projection of the Euler guess onto
/// `next`.
Vec3 advect_target(const SurfacePoint& from, const SurfaceIndex& previous, const SurfaceIndex& next, double dt,
                   Advection scheme);

}  // namespace fluidtex
