/// @file distortion.h
/// @brief Patch distortion (Gagnon et al. 2019, Sec. 5.3) with the metric of
/// Sorkine et al. 2002, "Bounded-distortion piecewise mesh parameterization"
/// (as used by Yu et al. 2011, Sec. 3.3.3).
///
/// For a triangle with rest shape (s_i, t_i) in 2D and current corners q_i in
/// 3D, the affine map's Jacobian columns are
///   S_s = (q1(t2−t3) + q2(t3−t1) + q3(t1−t2)) / (2A),
///   S_t = (q1(s3−s2) + q2(s1−s3) + q3(s2−s1)) / (2A),
/// with A the rest area; its singular values are
///   γ_max,min = sqrt(½((a + c) ± sqrt((a − c)² + 4b²))), a = S_s·S_s, b = S_s·S_t, c = S_t·S_t,
/// and the distortion is D_T = max(γ_max, 1/γ_min) (1 for an isometry).
#pragma once

#include <array>

#include "fluidtex/geometry/mesh.h"

namespace fluidtex {

/// The rest shape of a triangle: its corners in a local 2D frame.
using RestTriangle = std::array<Vec2, 3>;

/// Lays a 3D triangle flat (corner 0 at the origin, edge 01 along +s).
RestTriangle rest_shape(const Vec3& p0, const Vec3& p1, const Vec3& p2);

struct Stretch {
  double gamma_max = 1.0;
  double gamma_min = 1.0;
};

/// Singular values of the map rest → current. A degenerate rest or current
/// triangle gives gamma_min = 0 (infinite distortion).
Stretch triangle_stretch(const RestTriangle& r, const Vec3& q1, const Vec3& q2, const Vec3& q3);

/// D_T = max(γ_max, 1/γ_min) ≥ 1; +infinity when degenerate.
double triangle_distortion(const RestTriangle& rest, const Vec3& q0, const Vec3& q1, const Vec3& q2);

/// Q_T = max((δmax − D_T)/(δmax − 1), 0) ∈ [0, 1].
double triangle_quality(double distortion, double max_distortion);

}  // namespace fluidtex
