// The 3D `drop` scene: a liquid sphere falling into a pool and merging with
// it (after the viscous drop of Gagnon et al. 2019, Fig. 13, and [GDP16]).
//
// Geometry (scene units, z up):
//  - pool: the rounded box [-1,1] x [-1,1] x [-0.5,0] (edge radius 0.08), a
//    closed surface;
//  - drop: a sphere of radius 0.25 centred at (0.12, -0.08, z(t));
//  - the liquid is the smooth union F = smin(sphere, pool; k = 0.12) with the
//    quadratic polynomial smooth minimum, so a neck forms across the thin gap
//    just before contact and the shapes merge into one afterwards.
// Motion: free fall from rest until the sphere's bottom touches the pool
// surface at the middle of the sequence (the gravity g = 2 H / t_c^2 is set
// from the fall height H = 0.45 and the contact time t_c = T / 2), then the
// drop is slowed down exponentially by the pool (continuous velocity) while
// it sinks a further 0.35 units, leaving a smooth mound.
//
// Each frame samples F into a narrow-band OpenVDB level set (voxel size
// 2.2 / resolution, half-width 3 voxels, signed flood fill), extracts the
// surface with volumeToMesh (adaptivity 0) and splits the quads along their
// shorter diagonal, with normals pointing out of the liquid.
// Velocities: the blend v_b = h v_sphere + (1 - h) v_pool (v_pool = 0, h the
// smooth-min's mixing weight, exactly dF/d(sphere SDF)), corrected along
// grad F so that the level set is carried exactly to first order:
// v = v_b - (dF/dt + v_b . grad F) grad F / (|grad F|^2 + 0.1^2).
// The correction is zero away from the neck.
#include <algorithm>
#include <cmath>

#include "fluidtex/util/error.h"
#include "scene_drop.h"
#include "scene_volume.h"

namespace fluidtex::detail {

namespace {

struct DropScene {
  Pool pool;
  // Drop.
  double radius = 0.25;
  Vec2 drop_xy{0.12, -0.08};
  double fall_height = 0.45;  // gap between the drop's bottom and the pool at t = 0
  double sink_depth = 0.35;   // how far the drop sinks after contact
  double blend = 0.12;        // smooth-min width k
  // Timing (set from the options).
  double t_contact = 1.0;
  double gravity = 1.0;

  explicit DropScene(const SceneOptions& options) {
    t_contact = 0.5 * options.duration();
    gravity = 2.0 * fall_height / (t_contact * t_contact);
  }

  double contact_speed() const { return gravity * t_contact; }

  /// Height of the drop's centre and its vertical velocity at time t.
  void drop_motion(double t, double& z, double& vz) const {
    const double z_contact = radius;
    if (t <= t_contact) {
      // Free fall from rest at t = 0: z = z_contact + g (t_c^2 - t^2) / 2.
      z = z_contact + 0.5 * gravity * (t_contact * t_contact - t * t);
      vz = -gravity * t;
    } else {
      const double tau = sink_depth / contact_speed();
      const double e = std::exp(-(t - t_contact) / tau);
      z = z_contact - sink_depth * (1.0 - e);
      vz = -contact_speed() * e;
    }
  }

  /// Smooth union; `h` returns the sphere's weight (dF / d sphere_sdf).
  double sdf(const Vec3& p, double z, double* h = nullptr) const {
    const double a = (p - Vec3(drop_xy.x(), drop_xy.y(), z)).norm() - radius;
    return smooth_union(a, pool.distance(p), blend, h);
  }

  Vec3 velocity(const Vec3& p, double z, double vz) const {
    double h = 0.0;
    sdf(p, z, &h);
    const Vec3 v_drop(0.0, 0.0, vz);
    const Vec3 vb = h * v_drop;
    // dF/dt = h * d(sphere sdf)/dt = -h * v_drop . n_sphere.
    const Vec3 c(drop_xy.x(), drop_xy.y(), z);
    const Vec3 r = p - c;
    const Vec3 n_sphere = r.norm() > 1e-12 ? Vec3(r.normalized()) : Vec3::UnitZ();
    const double df_dt = -h * v_drop.dot(n_sphere);
    const Vec3 grad = field_gradient([&](const Vec3& q) { return sdf(q, z); }, p);
    return carry_level_set(vb, df_dt, grad);
  }
};

}  // namespace

FrameMesh make_drop_frame(int frame, const SceneOptions& options) {
  const DropScene scene(options);
  const double t = options.time_of(frame);
  double z = 0.0, vz = 0.0;
  scene.drop_motion(t, z, vz);

  // The box around the pool and the drop's current position.
  const Vec3 centre(scene.drop_xy.x(), scene.drop_xy.y(), z);
  const Vec3 lo = scene.pool.lo().cwiseMin(centre - Vec3::Constant(scene.radius));
  const Vec3 hi = scene.pool.hi().cwiseMax(centre + Vec3::Constant(scene.radius));
  FrameMesh mesh =
      mesh_distance_field([&](const Vec3& p) { return scene.sdf(p, z); }, lo, hi, volume_voxel_size(options));
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    mesh.velocities[v] = scene.velocity(mesh.positions[v], z, vz);
  }
  return mesh;
}

}  // namespace fluidtex::detail
