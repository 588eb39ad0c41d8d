/// @file advection.h
/// @brief Patch advection and projection (Gagnon et al. 2019, Sec. 5.2),
/// distortion estimation (Sec. 5.3) and vertex weights (Sec. 6.1–6.2).
///
/// Every vertex (and the disk centre) moves by the surface velocity at its
/// projection on the previous frame times dt, then snaps to the closest point
/// of the new frame's surface; a vertex farther than mpt from it is removed
/// with its triangles, and a centre farther than mpt kills its patch.
#pragma once

#include "fluidtex/tracking/options.h"
#include "fluidtex/tracking/patch.h"
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

/// Distortion of a patch on its current surface: per-triangle D_T (Sorkine),
/// per-vertex Q_V (mean Q_T of the incident triangles, weighted by their rest
/// area, a departure that keeps sliver triangles of reconstructed surfaces
/// from deciding alone) stored in
/// `patch.quality`, `patch.max_distortion` set. Returns the rule that found
/// the patch too distorted, None when it is fine.
///
/// DistortionTest::Patch (the default): the disk shows too little
/// undistorted texture, Σ seen_weight·Q_T < Q_vmin · patch.disk_weight over
/// its triangles, where flipped triangles, triangles across two surface
/// components and triangles lost in advection count Q_T = 0; the largest of
/// those losses names the cause (VerticesLost, Split, Flipped or Quality).
///
/// DistortionTest::Vertex: a triangle whose corners lie on different
/// connected components of the surface (Split), a triangle flipped against
/// the surface normal (Flipped), or a vertex with Q_V < Q_vmin (Quality), in
/// that order. Departure from the
/// paper, which tests every vertex: only vertices and triangles inside the
/// disk (|uv| < d, where K_S > 0) are tested, since the selection margin out
/// to (1 + β)d carries no weight and its distortion cannot be seen; on real
/// simulations this margin collapses on ridges and creases and would retire
/// most patches within a few frames.
RetireCause update_distortion(Patch& patch, const SurfaceIndex& surface, const TrackingOptions& options);

/// Weight of the coverage tail (see update_weights).
constexpr double kCoverageTail = 0.01;

/// The coverage tail at |V_uv − p_uv| = r (see update_weights):
/// kCoverageTail·max(0, 1 − r/((1 + β)d)).
double tail_weight(double r, const TrackingOptions& options);

/// The radial term of K_S at |V_uv − p_uv| = r (see update_weights): 1 − r/d
/// inside the disk plus the coverage tail out to (1 + β)d.
double radial_weight(double r, const TrackingOptions& options);

/// w_V = K_S(V)·K_t with Eq. 4, K_S = max(0, 1 − |V_uv − p_uv|/d_uv)·s·d_V·Q_V,
/// d_uv = d (uv is metric). Fills `patch.weight`.
///
/// Departure from the paper: a faint tail, kCoverageTail·max(0, 1 − r/((1+β)d)),
/// is added to the radial term. A Poisson distribution is maximal only up to
/// its candidate spacing, so slivers of surface slightly farther than d from
/// every disk exist; Eq. 4 alone gives them Σw = 0 (a hole showing the mean
/// colour). With the tail, they show the texture of the patches around them.
/// For the same reason Q_V enters K_S floored at kCoverageTail: where every
/// patch is distorted (Q_V = 0, already fading out and being replaced), the
/// surface shows their texture rather than a flat hole. Synthesis blends the
/// tail (w_V − core_weight) only where the core weights leave a point
/// (nearly) bare (SynthesisOptions::radius), so elsewhere a texel blends
/// exactly the paper's weights. d_V = 0 on the patch border zeroes the core,
/// not the tail: a patch the plane test cuts down to a few border triangles
/// (a droplet smaller than the disk) still covers its surface.
void update_weights(Patch& patch, const TrackingOptions& options);

/// The paper's w_V = K_S(V)·K_t at vertex v of `patch` (Eq. 4 and 2) without
/// the coverage tail or the Q_V floor of update_weights: the weight a patch
/// blends with where it covers a point with its disk. `radius` is d, `uv_scale` s.
/// Never above patch.weight[v]; the difference is the vertex's coverage tail,
/// which synthesis blends only where the disks leave the surface (nearly) bare.
float core_weight(const Patch& patch, std::size_t v, double radius, double uv_scale);

}  // namespace fluidtex
