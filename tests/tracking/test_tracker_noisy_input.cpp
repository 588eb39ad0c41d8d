// The tracker on noisy, re-meshed input (real caches churn): a sphere that
// translates or spins rigidly, re-meshed every frame, with 20 % velocity
// noise, keeps its patches and carries them with the motion.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "fluidtex/tracking/advection.h"
#include "fluidtex/tracking/patch_locator.h"
#include "fluidtex/tracking/tracker.h"
#include "fluidtex/util/random.h"
#include "mesh_fixtures.h"

namespace fluidtex {
namespace {

/// A rigid motion of the sphere: x(t) = R(ωt)(x0 − c) + c + V t.
struct RigidMotion {
  Vec3 centre = Vec3::Zero();
  Vec3 velocity = Vec3::Zero();  ///< V
  Vec3 spin = Vec3::Zero();      ///< ω (rad/s), about the moving centre
  Vec3 at(const Vec3& x0, double t) const {
    const double angle = spin.norm() * t;
    const Eigen::AngleAxisd r(angle, angle > 0.0 ? Vec3(spin.normalized()) : Vec3::UnitZ());
    return r * (x0 - centre) + centre + velocity * t;
  }
  Vec3 velocity_at(const Vec3& x, double t) const { return velocity + spin.cross(x - (centre + velocity * t)); }
};

/// Frame f of a sphere (radius 0.5) moving rigidly, re-meshed every frame (a
/// UV sphere whose poles turn to a new random axis), vertex velocities with
/// noise of `noise` × the local speed in a random direction.
std::shared_ptr<FrameMesh> noisy_sphere(const RigidMotion& m, int frame, double fps, double noise) {
  const double t = (frame - 1) / fps;
  FrameMesh s = test::uv_sphere(20, 40, 0.5);
  const Vec3 axis(uniform(7, Stream::Candidates, frame, 1) - 0.5, uniform(7, Stream::Candidates, frame, 2) - 0.5,
                  uniform(7, Stream::Candidates, frame, 3) - 0.5);
  const Eigen::AngleAxisd turn(2.0 * M_PI * uniform(7, Stream::Candidates, frame, 4), axis.normalized());
  const Vec3 centre = m.centre + m.velocity * t;
  for (std::size_t v = 0; v < s.positions.size(); ++v) {
    s.positions[v] = turn * s.positions[v] + centre;
    const Vec3 exact = m.velocity_at(s.positions[v], t);
    const Vec3 dir(uniform(9, Stream::Candidates, frame, v, 1) - 0.5, uniform(9, Stream::Candidates, frame, v, 2) - 0.5,
                   uniform(9, Stream::Candidates, frame, v, 3) - 0.5);
    s.velocities[v] = exact + noise * exact.norm() * dir.normalized();
  }
  return std::make_shared<FrameMesh>(std::move(s));
}

struct Survival {
  double births_per_live = 0.0;  ///< mean over frames 2..
  double kept = 0.0;             ///< share of the first frame's patches live and not fading out at the end
  double drift = 0.0;            ///< mean |centre − rigid image of its first position| / d over those
  double drift_max = 0.0;        ///< and the largest
};

/// The defaults (smooth motion, patch-scale test, plastic patches, kill
/// hysteresis, recut) or the paper's rules (per-vertex motion and test, no
/// relaxation, no hysteresis, distorted patches fade out).
Survival track_sphere(const RigidMotion& m, bool paper_rules, int frames = 36) {
  const double fps = 24.0;
  TrackerSettings settings;
  if (paper_rules) {
    settings.motion = PatchMotion::Vertex;
    settings.tracking.distortion_test = DistortionTest::Vertex;
    settings.tracking.relax_frames = 0;
    settings.tracking.kill_frames = 0;
    settings.tracking.birth_margin = 0.0;
    settings.tracking.projection_slack = 0.0;
    settings.tracking.distorted = Distorted::Fade;
  }
  Tracker tracker(settings);
  std::map<std::uint32_t, Vec3> first;
  double births = 0.0;
  for (int f = 1; f <= frames; ++f) {
    const StepReport r = tracker.step(noisy_sphere(m, f, fps, 0.2), f, 1.0 / fps);
    if (f == 1) {
      for (const Patch& p : tracker.patches()) first[p.id] = p.centre.point.position;
    } else {
      births += r.created / static_cast<double>(tracker.patches().size());
    }
  }
  Survival s;
  s.births_per_live = births / (frames - 1);
  const double t = (frames - 1) / fps, d = tracker.settings().tracking.d();
  int kept = 0;
  for (const Patch& p : tracker.patches()) {
    const auto it = first.find(p.id);
    if (it == first.end() || is_fading_out(p.state)) continue;
    ++kept;
    const double e = (p.centre.point.position - m.at(it->second, t)).norm() / d;
    s.drift += e;
    s.drift_max = std::max(s.drift_max, e);
  }
  s.drift /= std::max(kept, 1);
  s.kept = kept / static_cast<double>(first.size());
  return s;
}

TEST(RobustTracking, NoisyRemeshedTranslatingSphereKeepsItsPatches) {
  RigidMotion m;
  m.velocity = Vec3(0.6, 0.2, -0.1);
  const Survival s = track_sphere(m, false);
  EXPECT_LE(s.births_per_live, 0.01);
  EXPECT_GE(s.kept, 0.95);
  // Measured: 0.153 d on average, 0.42 d at most (1.4 % and 3.9 % of the
  // 0.95 m travelled): the map, fitted where the texture shows, averages the
  // noise over fewer vertices than a plain fit would (0.08 d), and follows
  // the real caches' velocities closer for it (docs/method.md).
  EXPECT_LE(s.drift, 0.2);
  EXPECT_LE(s.drift_max, 0.5);
  // The paper's per-vertex motion and test lose the same patches to the
  // noise (measured: 6 % of them left after 36 frames).
  const Survival paper = track_sphere(m, true);
  EXPECT_LT(paper.kept, s.kept - 0.3);
}

TEST(RobustTracking, NoisyRemeshedSpinningSphereKeepsItsPatches) {
  RigidMotion m;
  m.spin = Vec3(0.3, 0.2, 1.0);  // about 0.5 m/s at the equator, 1.6 rad over the run
  const Survival s = track_sphere(m, false);
  EXPECT_LE(s.births_per_live, 0.01);
  EXPECT_GE(s.kept, 0.95);
  EXPECT_LE(s.drift, 0.2);  // measured 0.124 d on average, 0.41 d at most
  EXPECT_LE(s.drift_max, 0.5);
  // Measured: 70 % kept (55 % with patch edges of d/4, whose small
  // triangles the noise crushes sooner).
  const Survival paper = track_sphere(m, true);
  EXPECT_LT(paper.kept, s.kept - 0.2);
}

}  // namespace
}  // namespace fluidtex
