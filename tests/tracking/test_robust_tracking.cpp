// Tracking on noisy, re-meshed input (issue: real caches churn): a sphere
// that translates or spins rigidly, re-meshed every frame, with 20 % velocity
// noise, must keep its patches and carry them with the motion; removal
// causes are counted; short cuts of the shared real caches keep churn bounded
// and the surface covered (skipped when ../shared is absent).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

#include "fluidtex/io/sequence.h"
#include "fluidtex/tracking/advection.h"
#include "fluidtex/tracking/patch_builder.h"
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
/// hysteresis) or the paper's rules (per-vertex motion and test, no
/// relaxation, no hysteresis).
Survival track_sphere(const RigidMotion& m, bool paper_rules, int frames = 36) {
  const double fps = 24.0;
  TrackerSettings settings;
  if (paper_rules) {
    settings.motion = PatchMotion::Vertex;
    settings.method.distortion_test = DistortionTest::Vertex;
    settings.method.relax_frames = 0;
    settings.method.kill_frames = 0;
  }
  Tracker tracker(settings);
  std::map<std::uint32_t, Vec3> first;
  double births = 0.0;
  for (int f = 1; f <= frames; ++f) {
    const StepReport r = tracker.step(noisy_sphere(m, f, fps, 0.2), f, 1.0 / fps);
    if (f == 1) {
      for (const Patch& p : tracker.patches()) first[p.id] = p.center.point.position;
    } else {
      births += r.created / static_cast<double>(tracker.patches().size());
    }
  }
  Survival s;
  s.births_per_live = births / (frames - 1);
  const double t = (frames - 1) / fps, d = tracker.settings().method.d();
  int kept = 0;
  for (const Patch& p : tracker.patches()) {
    const auto it = first.find(p.id);
    if (it == first.end() || is_fading_out(p.state)) continue;
    ++kept;
    const double e = (p.center.point.position - m.at(it->second, t)).norm() / d;
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
  // Measured: 0.154 d on average, 0.40 d at most (1.4 % and 3.7 % of the
  // 0.95 m travelled): the map, fitted where the texture shows, averages the
  // noise over fewer vertices than a plain fit would (0.08 d), and follows
  // the real caches' velocities closer for it (docs/method.md).
  EXPECT_LE(s.drift, 0.2);
  EXPECT_LE(s.drift_max, 0.5);
  // The paper's per-vertex motion and test lose the same patches to the
  // noise (measured: none of them left after 36 frames).
  const Survival paper = track_sphere(m, true);
  EXPECT_LT(paper.kept, s.kept - 0.3);
}

TEST(RobustTracking, NoisyRemeshedSpinningSphereKeepsItsPatches) {
  RigidMotion m;
  m.spin = Vec3(0.3, 0.2, 1.0);  // about 0.5 m/s at the equator, 1.6 rad over the run
  const Survival s = track_sphere(m, false);
  EXPECT_LE(s.births_per_live, 0.01);
  EXPECT_GE(s.kept, 0.95);
  EXPECT_LE(s.drift, 0.2);  // measured 0.101 d on average, 0.33 d at most
  EXPECT_LE(s.drift_max, 0.5);
  const Survival paper = track_sphere(m, true);  // measured: 55 % kept
  EXPECT_LT(paper.kept, s.kept - 0.3);
}

}  // namespace
}  // namespace fluidtex

namespace fluidtex {
namespace {

struct RealCut {
  double births_per_live = 0.0;  ///< mean over frames 2..
  double uncovered_max = 0.0;    ///< largest uncovered area share of a frame
  double kept = 0.0;             ///< share of the first frame's patches live and not fading out at the end
};

/// Tracks `frames` ("1-24") of a shared real cache; nullopt when it is absent.
std::optional<RealCut> track_real(const std::string& scene, const std::string& frames, TrackerSettings settings = {}) {
  const std::filesystem::path dir =
      std::filesystem::path(FLUIDTEX_SOURCE_DIR) / ".." / "shared" / "realdata" / ("blender-" + scene);
  if (!std::filesystem::exists(dir)) return std::nullopt;
  InputOptions in;
  in.pattern = (dir / (scene + ".####.ply")).string();
  in.frames = frames;
  const Sequence sequence(in);
  Tracker tracker(settings);
  RealCut cut;
  std::set<std::uint32_t> first;
  for (std::size_t i = 0; i < sequence.size(); ++i) {
    const int f = sequence.frames()[i];
    const StepReport r = tracker.step(std::make_shared<const FrameMesh>(sequence.load(i)), f, 1.0 / in.fps);
    const PatchCoverage coverage(tracker.patches(), tracker.settings().method.mpt());
    cut.uncovered_max = std::max(cut.uncovered_max, uncovered_area_fraction(*tracker.surface(), coverage));
    if (i == 0) {
      for (const Patch& p : tracker.patches()) first.insert(p.id);
      continue;
    }
    cut.births_per_live += r.created / static_cast<double>(tracker.patches().size()) / (sequence.size() - 1);
  }
  int kept = 0;
  for (const Patch& p : tracker.patches()) kept += first.count(p.id) && !is_fading_out(p.state);
  cut.kept = kept / static_cast<double>(first.size());
  return cut;
}

TEST(RealData, SloshKeepsItsPatchesAndStaysCovered) {
  const auto cut = track_real("slosh", "1-24");
  if (!cut) GTEST_SKIP() << "../shared/realdata is absent";
  // Measured before plastic patches (frames 1-24): births 3.3 % of the live patches per frame, 44 %
  // of the first frame's patches kept through the first half swing (the
  // liquid really stretches there, up to D ≈ 2); with the paper's rules
  // (per-vertex motion and test, Eq. 6): 7.9 % and 22 %.
  EXPECT_LE(cut->births_per_live, 0.04);
  EXPECT_GE(cut->kept, 0.4);
  EXPECT_EQ(cut->uncovered_max, 0.0);
}

TEST(RealData, DropChurnStaysBounded) {
  const auto cut = track_real("drop", "1-16");
  if (!cut) GTEST_SKIP() << "../shared/realdata is absent";
  // Measured before plastic patches (frames 1-16, through the impact): births 8.1 % per frame (the
  // paper's rules: 13 %), no bare surface (they leave 5.7e-5).
  EXPECT_LE(cut->births_per_live, 0.1);
  EXPECT_EQ(cut->uncovered_max, 0.0);
}

TEST(RealData, ObstacleSplashDropletsAreCovered) {
  const auto cut = track_real("obstacle", "12-22");
  if (!cut) GTEST_SKIP() << "../shared/realdata is absent";
  // The dam break's sheet tears into droplets smaller than the disk (frames
  // 14, 19, 21); the plane test cuts their patches down to border triangles.
  // Measured: no bare surface (8-12 bare faces per such frame before the
  // border tail and the refill), births 18 % of the live patches per frame.
  EXPECT_EQ(cut->uncovered_max, 0.0);
  EXPECT_LE(cut->births_per_live, 0.25);
}

// --- Removal causes -------------------------------------------------------------

/// A patch on a flat grid, then its positions mapped by `f`.
template <class F>
RetireCause judge(F&& f, DistortionTest test, bool drop_half = false) {
  const FrameMesh mesh = test::flat_grid(40);
  const SurfaceIndex surface(mesh);
  TrackingOptions o = TrackingOptions{}.resolved(1.0);
  o.radius = 0.15;
  o.distortion_test = test;
  SurfaceSample c;
  c.point = surface.closest_point(Vec3(0.5, 0.5, 0));
  c.normal = surface.normal_at(c.point);
  std::optional<Patch> p = build_patch(surface, c, o, 1, 1, 1, 0.0);
  if (!p) {
    ADD_FAILURE() << "no patch built";
    return RetireCause::None;
  }
  for (Vec3& x : p->positions) x = f(x);
  if (drop_half) {  // drop the vertices on one side of the centre (lost past mpt)
    std::vector<std::uint8_t> keep(p->positions.size(), 1);
    for (std::size_t v = 0; v < keep.size(); ++v) keep[v] = p->uvs[v].x() < -0.02 * o.d();
    remove_vertices(*p, keep, surface);
  }
  return update_distortion(*p, surface, o);
}

TEST(RetireCauses, TheRuleThatFiredIsNamed) {
  const Vec3 c(0.5, 0.5, 0);
  auto rigid = [&](const Vec3& x) { return Vec3(c + Eigen::AngleAxisd(0.7, Vec3::UnitZ()) * (x - c)); };
  auto stretched = [&](const Vec3& x) { return Vec3(c + Vec3(3.5 * (x - c).x(), (x - c).y(), 0)); };
  auto mirrored = [&](const Vec3& x) { return Vec3(c + Vec3(-(x - c).x(), (x - c).y(), 0)); };
  // A mild stretch on a few triangles: the patch-scale test keeps the patch,
  // the per-vertex one does not.
  auto bump = [&](const Vec3& x) {  // a strip 0.03 wide stretched 3×, the rest moved rigidly
    return Vec3(x + Vec3(2.0 * std::clamp(x.x() - c.x() - 0.02, 0.0, 0.03), 0, 0));
  };
  for (DistortionTest test : {DistortionTest::Patch, DistortionTest::Vertex}) {
    SCOPED_TRACE(to_string(test));
    EXPECT_EQ(judge(rigid, test), RetireCause::None);
    EXPECT_EQ(judge(stretched, test), RetireCause::Quality);
    EXPECT_EQ(judge(mirrored, test), RetireCause::Flipped);
  }
  EXPECT_EQ(judge(rigid, DistortionTest::Patch, true), RetireCause::VerticesLost);
  EXPECT_EQ(judge(bump, DistortionTest::Patch), RetireCause::None);
  EXPECT_EQ(judge(bump, DistortionTest::Vertex), RetireCause::Quality);
}

// The patch-scale test weighs what the disk shows now: a band the flow has
// crushed into a sliver (a convergence line on a liquid surface, where
// surface material goes under) shows almost nothing, so it does not retire a
// patch whose other triangles are intact. Measured on blender-slosh before
// this rule: 546 of 561 patches retired as too distorted had their worst
// triangle compressed, not stretched (median smallest singular value 0.044).
TEST(RetireCauses, ACrushedBandShowsLittleAUniformSqueezeRetires) {
  const double band = 0.08, squeeze = 20.0;  // the band |x − 0.5| < band, crushed 20×; the disk radius is 0.15
  auto crush_band = [&](const Vec3& x) {
    const double u = x.x() - 0.5;
    const double crushed = std::abs(u) < band ? u / squeeze : std::copysign(band / squeeze + std::abs(u) - band, u);
    return Vec3(0.5 + crushed, x.y(), x.z());
  };
  EXPECT_EQ(judge(crush_band, DistortionTest::Patch), RetireCause::None);
  auto squeeze_all = [](const Vec3& x) { return Vec3(0.5 + (x.x() - 0.5) / 3.5, x.y(), x.z()); };  // D = 3.5 > δmax
  EXPECT_EQ(judge(squeeze_all, DistortionTest::Patch), RetireCause::Quality);
  // The paper's per-vertex test retires both.
  EXPECT_EQ(judge(crush_band, DistortionTest::Vertex), RetireCause::Quality);
}

/// Too-close retirements of a plane whose liquid converges towards x = 0 for
/// `converge` frames and then spreads back out, tracked for `frames`
/// frames; `first` is the first frame with one (0: none).
struct CloseRun {
  int too_close = 0, first = 0;
};
CloseRun converging_plane(int kill_frames, int converge, int frames) {
  TrackerSettings s;
  s.method.radius = 0.12;
  s.method.kill_frames = kill_frames;
  s.seed = 5;
  Tracker t(s);
  CloseRun run;
  for (int f = 1; f <= frames; ++f) {
    const double k = f <= converge ? -1.5 : 1.5;  // strain rate per second: 6 % per frame at 24 fps
    const auto velocity = [k](const Vec3& p) { return Vec3(k * p.x(), 0.0, 0.0); };
    const StepReport r =
        t.step(std::make_shared<FrameMesh>(test::flat_grid(24, 1.2, 0.0, -0.6, -0.6, velocity)), f, 1.0 / 24);
    for (const RetiredPatch& x : r.retired) {
      if (x.cause != RetireCause::TooClose) continue;
      ++run.too_close;
      if (!run.first) run.first = f;
    }
  }
  return run;
}

TEST(KillFrames, ACompressionTheLiquidUndoesRetiresNothing) {
  // Six frames of convergence bring disks within the kill distance; the
  // paper retires them at once. With kill-frames 8 they wait, the liquid
  // spreads out again, and none is retired.
  const CloseRun paper = converging_plane(0, 6, 16);
  const CloseRun wait = converging_plane(8, 6, 16);
  EXPECT_GT(paper.too_close, 0);
  EXPECT_EQ(wait.too_close, 0);
  // A sustained convergence still retires them, kill-frames frames later
  // than the paper's rule does.
  const CloseRun paper_long = converging_plane(0, 16, 16);
  const CloseRun wait_long = converging_plane(4, 16, 16);
  ASSERT_GT(paper_long.first, 0);
  ASSERT_GT(wait_long.first, 0);
  EXPECT_GE(wait_long.first, paper_long.first + 4);
  EXPECT_LT(wait_long.too_close, paper_long.too_close);
}

TEST(RetireCauses, CountsAndAgeBuckets) {
  EXPECT_EQ(age_bucket(0), 0);
  EXPECT_EQ(age_bucket(1), 0);
  EXPECT_EQ(age_bucket(2), 1);
  EXPECT_EQ(age_bucket(7), 2);
  EXPECT_EQ(age_bucket(8), 3);
  EXPECT_EQ(age_bucket(31), 4);
  EXPECT_EQ(age_bucket(32), 5);
  EXPECT_EQ(age_bucket(1000), 5);
  const auto counts =
      retired_counts({{1, RetireCause::Quality, 3}, {2, RetireCause::Quality, 40}, {5, RetireCause::TooClose, 0}});
  auto get = [&](const std::string& k) {
    for (const auto& [key, n] : counts)
      if (key == k) return n;
    ADD_FAILURE() << "no key " << k;
    return -1.0;
  };
  EXPECT_EQ(counts.size(), static_cast<std::size_t>(kRetireCauses - 1 + kAgeBuckets));
  EXPECT_EQ(get("retired_quality"), 2);
  EXPECT_EQ(get("retired_too_close"), 1);
  EXPECT_EQ(get("retired_flipped"), 0);
  EXPECT_EQ(get("retired_age_0_1"), 1);
  EXPECT_EQ(get("retired_age_2_3"), 1);
  EXPECT_EQ(get("retired_age_32_up"), 1);
}

}  // namespace
}  // namespace fluidtex
