// The 3D scenes' level-set toolkit (scene_volume.cpp; not installed): a
// distance field meshed through OpenVDB, the pool, smooth unions and the
// velocity that carries a moving level set.
#pragma once

#include <functional>

#include "fluidtex/geometry/mesh.h"
#include "fluidtex/scenes/scene_options.h"

namespace fluidtex::detail {

/// The voxel size of the 3D scenes' level sets (and of --format vdb).
double volume_voxel_size(const SceneOptions& options);

/// A signed distance field (negative inside the liquid) in scene units.
using DistanceField = std::function<double(const Vec3&)>;

/// The surface of `field` inside the box [lo, hi] (padded by five voxels):
/// sampled into a narrow-band OpenVDB level set of the given voxel size
/// (half-width 3 voxels, signed flood fill) and meshed with volumeToMesh
/// (closed, outward-oriented triangles). Velocities are left zero.
FrameMesh mesh_distance_field(const DistanceField& field, const Vec3& lo, const Vec3& hi, double voxel);

/// The pool of the 3D scenes: the box [-1,1]² × [-0.5, top] (top 0 when
/// still) with its edges rounded by 0.08, a closed surface.
struct Pool {
  double half_width = 1.0;
  double bottom = -0.5;
  double round = 0.08;
  double distance(const Vec3& p, double top = 0.0) const;
  double area() const { return 4.0 * half_width * half_width; }
  Vec3 lo() const { return {-half_width, -half_width, bottom}; }
  Vec3 hi(double top = 0.0) const { return {half_width, half_width, top}; }
};

/// The quadratic smooth minimum of the distances a and b over width k;
/// `mix` receives a's weight (d/da), 1 where a alone counts.
double smooth_union(double a, double b, double k, double* mix = nullptr);

/// Central-difference gradient of `field` at p.
Vec3 field_gradient(const DistanceField& field, const Vec3& p);

/// A blended velocity v_b corrected along grad F so that the level set F = 0,
/// whose values change by dF/dt at p, is carried to first order:
/// v = v_b - (dF/dt + v_b . grad F) grad F / (|grad F|^2 + 0.1^2).
inline Vec3 carry_level_set(const Vec3& vb, double df_dt, const Vec3& grad) {
  return vb - (df_dt + vb.dot(grad)) / (grad.squaredNorm() + 0.01) * grad;
}

}  // namespace fluidtex::detail
