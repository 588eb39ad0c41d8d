/// @file weights.h
/// @brief The vertex weights a patch blends with (Gagnon et al. 2019,
/// Sec. 6.1–6.2, Eq. 2 and 4).
#pragma once

#include <cstddef>

#include "fluidtex/tracking/options.h"
#include "fluidtex/tracking/patch.h"

namespace fluidtex {

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
