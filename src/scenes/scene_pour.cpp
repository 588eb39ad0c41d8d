// The 3D `pour` scene: a jet from a nozzle plunging into a pool. Liquid
// enters at the nozzle every frame and the surface it carries is destroyed
// where the jet meets the pool: surface made and destroyed inside the scene
// (a tap, a waterfall, a pour into open water), where the open `stream`
// makes and destroys it at a window's edges.
//
// Geometry (scene units, z up):
//  - pool: the rounded box [-1,1] x [-1,1] x [-0.5, s(t)] (edge radius
//    0.08), its still level s(t) rising with the volume poured in;
//  - jet: about the vertical axis through (0.1, -0.05), from a flat nozzle
//    at z = 0.8 where it leaves at 1.5 units/s with radius 0.16, falling
//    under g = 4 units/s^2: speed v(z) = sqrt(v0^2 + 2 g (0.8 - z)), radius
//    r0 sqrt(v0 / v(z)) (the flux is kept), so the jet thins and its surface
//    is stretched along it as it falls. Its front, a sphere of the local
//    radius, leaves the nozzle at t = 0 and meets the pool about 9 frames
//    later (24 fps);
//  - the liquid is the smooth union of the two (quadratic smooth minimum,
//    k = 0.1): a fillet joins the jet to the pool once it has landed.
// Motion:
//  - the jet's liquid moves down at v(z), its front at the speed there;
//  - after the jet lands, the pool's top is drawn towards it (ramped in over
//    0.2 s), at 0.6 units/s at the jet's radius falling as
//    (r_j / r) e^{-(r - r_j) / 0.3} with the distance r from the axis and to
//    0 over the 0.2 units below the level: surface made over the pool, most
//    near the jet, and destroyed at the fillet with the jet's own;
//  - the level rises at the poured flux over the pool's area;
//  - the two blend with the smooth minimum's mixing weight and are carried
//    with the level set (carry_level_set, dF/dt by central differences in
//    time), except on the nozzle's cap, where the liquid enters along the
//    normal as it crosses a solver's inflow face.
// Each frame samples the field into a level set of voxel 2.2 / resolution
// (scene_volume.cpp).
#include <algorithm>
#include <cmath>

#include "scene_pour.h"
#include "scene_volume.h"

namespace fluidtex::detail {

namespace {

struct PourScene {
  Pool pool;
  Vec2 axis{0.1, -0.05};
  double nozzle = 0.8;
  double nozzle_radius = 0.16;
  double nozzle_speed = 1.5;
  double gravity = 4.0;
  double jet_bottom = -0.3;  // the jet ends inside the pool
  double blend = 0.1;
  double pool_speed = 0.6;
  double pool_reach = 0.3;  // e-folding distance of the pool's inflow beyond the jet
  double pool_depth = 0.2;  // the pool's inflow falls to 0 over this depth below the level
  double pool_ramp = 0.2;   // seconds over which the pool's inflow starts after landing

  double jet_speed(double z) const {
    return std::sqrt(nozzle_speed * nozzle_speed + 2.0 * gravity * std::max(0.0, nozzle - z));
  }
  double jet_radius(double z) const { return nozzle_radius * std::sqrt(nozzle_speed / jet_speed(z)); }
  /// Height of the jet's front at time t (it leaves the nozzle at t = 0).
  double front(double t) const { return std::max(nozzle - nozzle_speed * t - 0.5 * gravity * t * t, jet_bottom); }
  /// Time at which the front reaches the pool's starting level.
  double landing() const {
    return (-nozzle_speed + std::sqrt(nozzle_speed * nozzle_speed + 2.0 * gravity * nozzle)) / gravity;
  }
  double flux() const { return M_PI * nozzle_radius * nozzle_radius * nozzle_speed; }
  double rise_speed(double t) const { return t > landing() ? flux() / pool.area() : 0.0; }
  double level(double t) const { return rise_speed(t) * std::max(0.0, t - landing()); }

  /// Signed distance to the jet at time t (approximate: the radius changes
  /// slowly along it) and whether the nozzle's cap is its nearest part.
  double jet_sdf(const Vec3& p, double t, bool* on_cap = nullptr) const {
    const double rho = (p.head<2>() - axis).norm();
    const double z_front = front(t);
    const double r_front = jet_radius(z_front);
    const double tip = std::min(z_front + r_front, nozzle);  // the front sphere's centre
    const double radial = rho - jet_radius(std::clamp(p.z(), tip, nozzle));
    const double axial = std::max(p.z() - nozzle, tip - p.z());
    if (on_cap) *on_cap = p.z() > nozzle - 0.5 * nozzle_radius && axial > radial;
    const double column =
        std::min(std::max(radial, axial), 0.0) + Vec2(std::max(radial, 0.0), std::max(axial, 0.0)).norm();
    const double sphere = std::max(Vec2(rho, p.z() - tip).norm() - r_front, p.z() - nozzle);
    return std::min(column, sphere);
  }

  double sdf(const Vec3& p, double t, double* h = nullptr, bool* on_cap = nullptr) const {
    return smooth_union(jet_sdf(p, t, on_cap), pool.distance(p, level(t)), blend, h);
  }

  Vec3 pool_velocity(const Vec3& p, double t) const {
    const Vec2 out = p.head<2>() - axis;
    const double r_j = jet_radius(level(t));
    const double r = std::max(out.norm(), r_j);
    const double depth = std::clamp(1.0 + (p.z() - level(t)) / pool_depth, 0.0, 1.0);
    const double ramp = std::clamp((t - landing()) / pool_ramp, 0.0, 1.0);
    const double speed = pool_speed * ramp * (r_j / r) * std::exp(-(r - r_j) / pool_reach) * depth;
    const Vec2 in = out.norm() > 1e-12 ? Vec2(-out / out.norm()) : Vec2::Zero();
    return Vec3(speed * in.x(), speed * in.y(), rise_speed(t) * depth);
  }

  Vec3 velocity(const Vec3& p, double t) const {
    double h = 0.0;
    bool on_cap = false;
    sdf(p, t, &h, &on_cap);
    const double z_jet = std::max(p.z(), front(t));
    Vec3 vb = h * Vec3(0.0, 0.0, -jet_speed(z_jet)) + (1.0 - h) * pool_velocity(p, t);
    if (on_cap && h > 0.999) return vb;
    const double e = 1e-4;
    const double df_dt = (sdf(p, t + e) - sdf(p, std::max(0.0, t - e))) / (t + e - std::max(0.0, t - e));
    return carry_level_set(vb, df_dt, field_gradient([&](const Vec3& q) { return sdf(q, t); }, p));
  }
};

}  // namespace

FrameMesh make_pour_frame(int frame, const SceneOptions& options) {
  const PourScene scene;
  const double t = options.time_of(frame);
  FrameMesh mesh = mesh_distance_field([&](const Vec3& p) { return scene.sdf(p, t); }, scene.pool.lo(),
                                       scene.pool.hi(scene.nozzle), volume_voxel_size(options));
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) mesh.velocities[v] = scene.velocity(mesh.positions[v], t);
  return mesh;
}

}  // namespace fluidtex::detail
