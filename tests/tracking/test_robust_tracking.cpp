// Tracking on noisy, re-meshed input (issue: real caches churn): a sphere
// that translates or spins rigidly, re-meshed every frame, with 20 % velocity
// noise, must keep its patches and carry them with the motion; removal
// causes are counted; short cuts of the shared real caches keep churn bounded
// and the surface covered (skipped when ../shared is absent).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <set>

#include "fluidtex/io/sequence.h"
#include "fluidtex/tracking/advection.h"
#include "fluidtex/tracking/patch_builder.h"
#include "fluidtex/tracking/patch_coverage.h"
#include "fluidtex/tracking/patch_distortion.h"
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

namespace fluidtex {
namespace {

struct RealCut {
  double births_per_live = 0.0;  ///< mean over frames 2..
  double uncovered_max = 0.0;    ///< largest uncovered area share of a frame
  double kept = 0.0;             ///< share of the first frame's patches live and not fading out at the end
  double crowding = 1.0;         ///< largest patch count per unit area over the first frame's
  /// New disks inside a live patch that waits out kill-frames (within the
  /// kill distance of an older disk: close_frames > 0), its K_S > 0 at the
  /// new centre; counted once per such patch.
  int born_in_waiting = 0;
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
  double first_density = 0.0;
  for (std::size_t i = 0; i < sequence.size(); ++i) {
    const int f = sequence.frames()[i];
    const StepReport r = tracker.step(std::make_shared<const FrameMesh>(sequence.load(i)), f, 1.0 / sequence.fps());
    const double mpt = tracker.settings().tracking.mpt();
    for (const Patch& born : tracker.patches()) {
      if (i == 0 || born.created_frame != f) continue;
      for (const Patch& p : tracker.patches()) {
        cut.born_in_waiting += p.created_frame < f && p.close_frames > 0 && !is_fading_out(p.state) &&
                               patch_covers(p, born.centre.point.position, born.centre.normal, mpt);
      }
    }
    const PatchCoverage coverage(tracker.patches(), mpt);
    cut.uncovered_max =
        std::max(cut.uncovered_max, uncovered_area_fraction(*tracker.surface(), coverage, tracker.coverage_spacing()));
    const double density = static_cast<double>(tracker.patches().size()) / tracker.surface()->area();
    if (i == 0) {
      first_density = density;
      for (const Patch& p : tracker.patches()) first.insert(p.id);
      continue;
    }
    cut.crowding = std::max(cut.crowding, density / first_density);
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
  // Measured (frames 1-24): births 0.35 % of the
  // live patches per frame, 91 % of the first frame's patches kept through
  // the first half swing (the liquid really stretches there, up to D ≈ 2);
  // --birth-gap centres: 0.8 %, 91 %. Earlier (centres): --birth-margin 0:
  // 1.5 %, 92 %; with --distorted fade 2.0 % and 74 %; before plastic
  // patches 3.3 % and 44 %; with the paper's rules (per-vertex motion and
  // test, Eq. 6): 7.9 % and 22 %.
  EXPECT_LE(cut->births_per_live, 0.02);
  EXPECT_GE(cut->kept, 0.85);
  EXPECT_EQ(cut->uncovered_max, 0.0);
  // Patches per unit area, largest over the first frame's: 1.08 (--birth-gap
  // centres 1.21, and --birth-margin 0 1.41; drop 1.05 / 1.30 in the test
  // below).
  EXPECT_LE(cut->crowding, 1.15);
  // A disk waiting out kill-frames counts as cover: no disk was born inside
  // one (gaps wider than (1 + γ)d that it covers); 8 with --birth-gap
  // centres, 24 when its area counted as bare too.
  EXPECT_LE(cut->born_in_waiting, 12);
}

TEST(RealData, DropChurnStaysBounded) {
  const auto cut = track_real("drop", "1-16");
  if (!cut) GTEST_SKIP() << "../shared/realdata is absent";
  // Measured (frames 1-16, through the impact):
  // births 1.6 % per frame, 84 % of the first frame's patches kept, and
  // patches per area at most 1.05× the first frame's (--birth-gap centres:
  // 3.0 %, 84 %, 1.30×; earlier, centres: --birth-margin 0: 4.4 %, 71 %;
  // --distorted fade: 7.5 %, 62 %; before plastic patches 8.1 %; the
  // paper's rules: 13 %), no bare surface (the paper's rules leave 5.7e-5).
  EXPECT_LE(cut->births_per_live, 0.055);
  EXPECT_GE(cut->kept, 0.65);
  EXPECT_EQ(cut->uncovered_max, 0.0);
  EXPECT_LE(cut->crowding, 1.15);
}

TEST(RealData, ObstacleSplashDropletsAreCovered) {
  const auto cut = track_real("obstacle", "12-22");
  if (!cut) GTEST_SKIP() << "../shared/realdata is absent";
  // The dam break's sheet tears into droplets smaller than the disk (frames
  // 14, 19, 21); the plane test cuts their patches down to border triangles.
  // Measured: no bare surface (8-12 bare faces per such frame before the
  // border tail and the refill), births 6.2 % of the live patches per frame
  // and 81 % of the first frame's patches kept (--birth-gap
  // centres: 8.5 %, 81 %; earlier, centres, with patch edges
  // of d/4: 7.4 %, 91 %; --birth-margin 0: 9.4 %, 85 %; --distorted fade:
  // 18 %, 38 %). Patches per area never above the first frame's (the
  // sheet spreads), 1.24× with --birth-gap centres. The sink rule retires
  // pairs where the falling column and the sheet merge without the
  // kill-frames wait: 70 % of the first frame's patches kept (81 % with
  // --sink keep).
  EXPECT_EQ(cut->uncovered_max, 0.0);
  EXPECT_LE(cut->births_per_live, 0.12);
  EXPECT_GE(cut->kept, 0.65);
  EXPECT_LE(cut->crowding, 1.15);
}

TEST(RealData, RiverPatchesStayAtTheirDensity) {
  // An inflow at one end, an outflow at the other: surface made and
  // destroyed every frame. Frames 49-96, where the stream has settled.
  // Measured: patches per area at most 1.02× the first frame's, births
  // 1.5 % of the live patches per frame, no bare surface; without the gap
  // fill and the sink rule (the paper's) 1.16×, the count climbing along
  // the outflow.
  const auto cut = track_real("river", "49-96");
  if (!cut) GTEST_SKIP() << "../shared/realdata is absent";
  TrackerSettings paper;
  paper.tracking.gap_fill = GapFill::Seed;
  paper.tracking.sink = Sink::Keep;
  const auto piled = track_real("river", "49-96", paper);
  EXPECT_LE(cut->crowding, 1.1);
  EXPECT_GT(piled->crowding, cut->crowding + 0.08);
  EXPECT_LE(cut->births_per_live, 0.05);
  EXPECT_EQ(cut->uncovered_max, 0.0);
}

TEST(RealData, ObstacleFoldedFaceIsCovered) {
  const auto cut = track_real("obstacle", "1-20");
  if (!cut) GTEST_SKIP() << "../shared/realdata is absent";
  // Frame 20 has a folded face (8.5e-6 m², a millionth of the surface): its
  // vertex normals point to both sides, and their blend points behind it
  // over part of the face. Coverage, tested along that blend, found 1.1e-7
  // of the area bare through every refill round; along the face's own
  // normal (SurfaceIndex::normal_at) the patches around it cover it.
  EXPECT_EQ(cut->uncovered_max, 0.0);
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
  int distorted = 0;  ///< retired as too distorted (any rule but centre lost, emptied and too close)
  int recut = 0;
  int recut_seen = 0;  ///< patches whose recut_frame is the step's frame, counted from the tracker's patches
  std::array<int, kRetireCauses> recut_causes{};  ///< the recuts by the rule that found the patch distorted
  int regrown = 0;
  int sunk = 0, first_sunk = 0;
  double uncovered_max = 0.0;
  double density_end = 0.0;  ///< patches per area on the last frame of the convergence over the first frame's
};
/// A plane whose liquid converges towards x = 0 for `converge` frames (the
/// surface destroyed there at `rate` per second) and spreads out again until
/// `frames`. The sink rule is off unless `sink` says otherwise: the wait and
/// the recut are what most callers compare.
CloseRun converging_plane(int kill_frames, int converge, int frames, double rate = 1.5,
                          Distorted distorted = Distorted::Recut, Sink sink = Sink::Keep) {
  TrackerSettings s;
  s.tracking.radius = 0.12;
  s.tracking.kill_frames = kill_frames;
  s.tracking.distorted = distorted;
  s.tracking.sink = sink;
  s.seed = 5;
  Tracker t(s);
  CloseRun run;
  double first_count = 1.0;
  for (int f = 1; f <= frames; ++f) {
    const double k = f <= converge ? -rate : rate;  // strain rate per second (1.5: 6 % per frame at 24 fps)
    const auto velocity = [k](const Vec3& p) { return Vec3(k * p.x(), 0.0, 0.0); };
    const StepReport r =
        t.step(std::make_shared<FrameMesh>(test::flat_grid(24, 1.2, 0.0, -0.6, -0.6, velocity)), f, 1.0 / 24);
    run.recut += r.recut;
    run.regrown += r.regrown;
    for (int c = 0; c < kRetireCauses; ++c) run.recut_causes[c] += r.recut_causes[c];
    run.recut_seen += static_cast<int>(
        std::count_if(t.patches().begin(), t.patches().end(), [&](const Patch& p) { return p.recut_frame == f; }));
    for (const RetiredPatch& x : r.retired) {
      if (x.cause == RetireCause::CentreLost || x.cause == RetireCause::Emptied) continue;
      if (x.cause == RetireCause::Sunk) {
        if (!run.sunk) run.first_sunk = f;
        ++run.sunk;
        continue;
      }
      if (x.cause != RetireCause::TooClose) {
        ++run.distorted;
        continue;
      }
      ++run.too_close;
      if (!run.first) run.first = f;
    }
    const PatchCoverage coverage(t.patches(), t.settings().tracking.mpt());
    run.uncovered_max =
        std::max(run.uncovered_max, uncovered_area_fraction(*t.surface(), coverage, t.coverage_spacing()));
    // The window's area is fixed: patches per area over the first frame's
    // is the patch count's ratio.
    if (f == 1) first_count = static_cast<double>(t.patches().size());
    if (f == converge) run.density_end = static_cast<double>(t.patches().size()) / first_count;
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

/// Births and the live patch count (not fading out) at the first and last
/// frame of a sheet of liquid that stretches along x for `stretch` frames
/// (the mesh itself widens, 6 % per frame) and then shrinks back as long.
struct StretchRun {
  int births = 0, first = 0, last = 0;
  double uncovered_max = 0.0;  ///< the largest uncovered area fraction of any frame
};
StretchRun stretching_sheet(double birth_margin, int stretch, BirthGap gap) {
  TrackerSettings s;
  s.tracking.radius = 0.12;
  s.tracking.birth_margin = birth_margin;
  s.tracking.birth_gap = gap;
  // The birth rules alone: the sink rule would thin the crowd the ratchet
  // leaves as the sheet narrows back.
  s.tracking.sink = Sink::Keep;
  s.seed = 5;
  Tracker t(s);
  StretchRun run;
  const double rate = 1.5, dt = 1.0 / 24;  // strain rate per second
  double width = 1.0;
  for (int f = 1; f <= 2 * stretch + 1; ++f) {
    const double k = f <= stretch ? rate : -rate;
    // This frame's velocity carries it to the next (the solver's convention).
    const double carry = std::expm1(k * dt) / dt;
    FrameMesh mesh = test::flat_grid(24, 1.2, 0.0, -0.6, -0.6);
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      mesh.positions[v].x() *= width;
      mesh.velocities[v] = Vec3(carry * mesh.positions[v].x(), 0.0, 0.0);
    }
    const StepReport r = t.step(std::make_shared<FrameMesh>(std::move(mesh)), f, dt);
    (f == 1 ? run.first : run.births) += r.created;
    const PatchCoverage coverage(t.patches(), t.settings().tracking.mpt());
    run.uncovered_max =
        std::max(run.uncovered_max, uncovered_area_fraction(*t.surface(), coverage, t.coverage_spacing()));
    width *= std::exp(k * dt);
  }
  for (const Patch& p : t.patches()) run.last += !is_fading_out(p.state);
  return run;
}

TEST(Sink, WhereTheLiquidKeepsConvergingPairsGoWithoutTheWait) {
  // 16 frames of convergence at 6 % a frame: the surface around every disk
  // loses the kill distance's α = 25 % of its area in under 5 frames and
  // does not come back. Without the sink rule a pair within the kill
  // distance waits kill-frames (8) frames and the crowd grows meanwhile;
  // with it, the pair's flagged disk fades out as soon as that loss is
  // reached, as "sunk", and the surface stays covered.
  const CloseRun keep = converging_plane(8, 16, 16, 1.5, Distorted::Recut, Sink::Keep);
  const CloseRun fade = converging_plane(8, 16, 16, 1.5, Distorted::Recut, Sink::Fade);
  EXPECT_EQ(keep.sunk, 0);
  ASSERT_GT(keep.first, 0);
  ASSERT_GT(fade.sunk, 0);
  EXPECT_LT(fade.first_sunk, keep.first);
  EXPECT_LT(fade.density_end, keep.density_end);
  EXPECT_EQ(fade.uncovered_max, 0.0);
}

TEST(BirthMargin, AStretchTheLiquidUndoesLeavesFewerPatches) {
  // The sheet widens 1.65-fold in 8 frames and narrows back. Seeding every
  // gap wider than d as it opens (margin 0) and retiring only disks within
  // 0.75 d that stay so for 8 frames leaves 1.8 times the first frame's
  // patches on the same area (measured 70 -> 111, 41 births); with the
  // margin, gaps must grow past 1.3 d first (70 -> 73, 3 births). Gaps
  // measured from the disk centres only, as the paper does: the margin
  // alone.
  const StretchRun paper = stretching_sheet(0.0, 8, BirthGap::Centres);
  const StretchRun margin = stretching_sheet(0.3, 8, BirthGap::Centres);
  ASSERT_EQ(paper.first, margin.first);
  EXPECT_GT(paper.last, 1.5 * paper.first);
  EXPECT_LT(margin.births, paper.births / 2);
  EXPECT_LT(margin.last, 1.35 * margin.first);
}

TEST(BirthMargin, AGapInsideAStretchedPatchSeedsNothing) {
  // The same sheet at the default margin: measured from the disk centres,
  // the stretch seeds disks between them; measured in the uv of the patches
  // over the candidates too, the gaps open inside patches that still show
  // their disks there, and the sheet keeps its first frame's patches.
  const StretchRun spread = stretching_sheet(0.15, 8, BirthGap::Centres);
  const StretchRun held = stretching_sheet(0.15, 8, BirthGap::Patches);
  ASSERT_EQ(spread.first, held.first);
  // Measured: 70 patches on the first frame; 13 births and 83 live patches
  // at the end from the centres, none and 70 in the patches.
  EXPECT_GE(spread.births, 8);
  EXPECT_GE(spread.last, spread.first + 8);
  EXPECT_LE(held.births, 3);
  EXPECT_LE(held.last, held.first + 3);
  EXPECT_EQ(spread.uncovered_max, 0.0);
  EXPECT_EQ(held.uncovered_max, 0.0);
}

// --- Recut ---------------------------------------------------------------------

/// The texture coordinate (before anchor and scale) that `patch` shows at the
/// surface point `q` (normal `n`), through its nearest triangle there; false
/// where it does not cover q.
bool texture_at(const Patch& patch, const Vec3& q, const Vec3& n, double tolerance, Vec2& texture) {
  double best = std::numeric_limits<double>::infinity();
  for (const Tri& t : patch.triangles) {
    Vec3 bary;
    double dist2 = 0.0;
    if (!project_to_patch_triangle(patch, t, q, n, tolerance, bary, dist2) || !(dist2 < best)) continue;
    best = dist2;
    texture = patch.texture_offset + interpolate(patch.uvs, t, bary);
  }
  return std::isfinite(best);
}

/// A patch of disk radius `radius` built at `c0` on a flat unit grid, then
/// deformed by a map of the plane (as advection would leave it), and recut.
class FlatRecut {
 public:
  FlatRecut(double radius, const Vec3& c0) : mesh_(test::flat_grid(40)), surface_(mesh_), c0_(c0) {
    o_ = TrackingOptions{}.resolved(1.0);
    o_.radius = radius;
    SurfaceSample c;
    c.point = surface_.closest_point(c0);
    c.normal = surface_.normal_at(c.point);
    old_ = build_patch(surface_, c, o_, 7, 1, 1, 0.25 * o_.d());
  }
  bool built() const { return old_.has_value(); }
  Patch& old() { return *old_; }
  const TrackingOptions& options() const { return o_; }
  /// Moves the old patch's vertices and centre by `f`; returns update_distortion's verdict.
  template <class F>
  RetireCause deform(F&& f) {
    for (std::size_t v = 0; v < old_->num_vertices(); ++v) {
      old_->projections[v] = surface_.closest_point(f(old_->positions[v]));
      old_->positions[v] = old_->projections[v].position;
    }
    old_->centre.point = surface_.closest_point(f(c0_));
    return update_distortion(*old_, surface_, o_);
  }
  std::optional<Patch> recut() {
    std::optional<Patch> cut = recut_patch(*old_, surface_, o_, 1, 9, 0.25 * o_.d());
    if (cut) update_distortion(*cut, surface_, o_);
    return cut;
  }
  /// The old patch's texture coordinate at `q`.
  bool old_texture(const Vec3& q, Vec2& texture) const {
    return texture_at(*old_, q, Vec3::UnitZ(), o_.mpt(), texture);
  }

 private:
  FrameMesh mesh_;
  SurfaceIndex surface_;  // refers to mesh_
  Vec3 c0_;
  TrackingOptions o_;
  std::optional<Patch> old_;
};

TEST(Recut, ARigidlyMovedPatchKeepsItsTextureAndItsPlace) {
  const Vec3 c0(0.45, 0.5, 0);
  FlatRecut bench(0.15, c0);
  ASSERT_TRUE(bench.built());
  const double d = bench.options().d();
  Patch& old = bench.old();
  old.texture_offset = Vec2(0.3, -0.2);
  // Its texture shifted under it (uv 0 no longer at its centre): the fit
  // must shift the new texture too.
  for (Vec2& uv : old.uvs) uv += Vec2(0.02, -0.01);
  old.anchor = Vec2(0.25, 0.75);
  old.state = DiskState::FadingIn, old.kt = 0.4, old.created_frame = -5, old.close_frames = 2;
  // Turned 0.7 rad about its centre and carried along: its uv no longer
  // line up with a fresh flattening's.
  const Eigen::AngleAxisd turn(0.7, Vec3::UnitZ());
  const Vec3 shift(0.06, 0.02, 0.0);
  ASSERT_EQ(bench.deform([&](const Vec3& x) { return Vec3(turn * (x - c0) + c0 + shift); }), RetireCause::None);

  const std::optional<Patch> cut = bench.recut();
  ASSERT_TRUE(cut);
  EXPECT_EQ(cut->id, 7u);
  EXPECT_EQ(cut->state, DiskState::FadingIn);
  EXPECT_EQ(cut->kt, 0.4);
  EXPECT_EQ(cut->created_frame, -5);
  EXPECT_EQ(cut->recut_frame, 9);
  EXPECT_EQ(cut->close_frames, 2);
  EXPECT_EQ(cut->anchor, old.anchor);
  EXPECT_EQ(cut->centre.point.position, old.centre.point.position);
  int compared = 0;
  double worst = 0.0;
  for (std::size_t v = 0; v < cut->num_vertices(); ++v) {
    Vec2 before;
    // Inside the old patch's rim (just outside it, the projection's slack
    // clamps onto the rim).
    if (!bench.old_texture(cut->positions[v], before)) continue;
    if ((before - old.texture_offset).norm() > 1.5 * d) continue;
    ++compared;
    worst = std::max(worst, (cut->texture_offset + cut->uvs[v] - before).norm());
    // It shows there what the old patch showed: all of it.
    if ((before - old.texture_offset).norm() < d) EXPECT_NEAR(cut->recovery[v], 1.0, 1e-6);
  }
  EXPECT_GT(compared, 50);
  EXPECT_LT(worst, 1e-6 * d);
  // Its uv still have the disk centre at the origin (K_S's radial term).
  Vec2 centre;
  ASSERT_TRUE(texture_at(*cut, cut->centre.point.position, Vec3::UnitZ(), bench.options().mpt(), centre));
  EXPECT_LT((centre - cut->texture_offset).norm(), 1e-6);
}

TEST(Recut, WhereThePatchWasCrushedTheNewTextureFadesIn) {
  FlatRecut bench(0.15, Vec3(0.45, 0.5, 0));
  ASSERT_TRUE(bench.built());
  const double d = bench.options().d();
  // The band 0.5 < x < 0.58 crushed 20× (a convergence line), what lies
  // beyond it carried along.
  auto crush = [](double x) { return x < 0.5 ? x : x < 0.58 ? 0.5 + (x - 0.5) / 20 : x - 0.08 + 0.08 / 20; };
  bench.deform([&](const Vec3& x) { return Vec3(crush(x.x()), x.y(), 0.0); });
  const std::optional<Patch> cut = bench.recut();
  ASSERT_TRUE(cut);
  double intact_error = 0.0, band_recovery = 0.0, intact_recovery = 0.0;
  int intact = 0, band = 0;
  for (std::size_t v = 0; v < cut->num_vertices(); ++v) {
    const Vec3& x = cut->positions[v];
    Vec2 before;
    if (cut->uvs[v].norm() > d || !bench.old_texture(x, before)) continue;
    if (x.x() < 0.49) {  // left of the band: moved rigidly (not at all)
      ++intact;
      intact_error += (cut->texture_offset + cut->uvs[v] - before).norm();
      intact_recovery += cut->recovery[v];
    } else if (std::abs(x.x() - 0.502) < 0.015) {  // at the crushed band
      ++band;
      band_recovery += cut->recovery[v];
    }
  }
  ASSERT_GT(intact, 10);
  ASSERT_GT(band, 0);
  // Left of the band the texture stays exactly and shows fully; at the band,
  // where the old patch's Q_V fell (half its triangles crushed), the new
  // patch starts at what it showed.
  EXPECT_LT(intact_error / intact, 1e-6 * d);
  EXPECT_GT(intact_recovery / intact, 0.99);
  EXPECT_LT(band_recovery / band, 0.6);
}

TEST(Recut, AStretchedPatchIsCutUndistortedAroundTheSameTexture) {
  const Vec3 c0(0.5, 0.5, 0);
  FlatRecut bench(0.12, c0);
  ASSERT_TRUE(bench.built());
  const double d = bench.options().d();
  // Stretched 2.5× along x.
  ASSERT_NE(bench.deform([&](const Vec3& x) { return Vec3(c0.x() + 2.5 * (x.x() - c0.x()), x.y(), 0.0); }),
            RetireCause::None);
  const std::optional<Patch> cut = bench.recut();
  ASSERT_TRUE(cut);
  EXPECT_LT(cut->max_distortion, 1.01);
  // Along the line the stretch left alone (x = 0.5) the texture is where it
  // was; away from it, the stretch is gone.
  int on_line = 0;
  double line_error = 0.0, off_error = 0.0;
  for (std::size_t v = 0; v < cut->num_vertices(); ++v) {
    Vec2 before;
    if (cut->uvs[v].norm() > d || !bench.old_texture(cut->positions[v], before)) continue;
    const double error = (cut->texture_offset + cut->uvs[v] - before).norm();
    if (std::abs(cut->positions[v].x() - c0.x()) < 1e-3 * d) {
      ++on_line, line_error = std::max(line_error, error);
    } else {
      off_error = std::max(off_error, error);
    }
  }
  ASSERT_GT(on_line, 2);
  EXPECT_LT(line_error, 1e-6 * d);
  EXPECT_GT(off_error, 0.1 * d);
}

TEST(Recut, APatchWhoseCentreMissesTheSurfaceIsMovedAndRecutNotLost) {
  // Still liquid whose next frame has sunk by 2 mpt within `r` of a patch's
  // centre (a closed surface moving away, not a hole: a hole's rim would be
  // an outflow): the centre misses the surface by more than mpt, most of
  // the patch still lies on it.
  const FrameMesh before = test::flat_grid(40);
  const SurfaceIndex previous(before);
  const Vec3 c0(0.45, 0.5, 0);
  TrackingOptions o = TrackingOptions{}.resolved(1.0);
  o.radius = 0.15;
  const double depth = 2.0 * o.mpt();
  const auto sunk = [&](double r) {
    FrameMesh m = before;
    for (Vec3& p : m.positions) {
      if ((p - c0).norm() < r) p.z() -= depth;
    }
    return m;
  };
  const FrameMesh after = sunk(0.1);
  const SurfaceIndex next(after);
  ASSERT_GT((next.closest_point(c0).position - c0).norm(), o.mpt());
  SurfaceSample c;
  c.point = previous.closest_point(c0);
  c.normal = previous.normal_at(c.point);
  const std::optional<Patch> built = build_patch(previous, c, o, 7, 1, 1, 0.25 * o.d());
  ASSERT_TRUE(built);
  const auto advect = [&](Patch& patch, const SurfaceIndex& to) {
    return advect_patch(patch, previous, to, 1.0 / 24, o, Advection::Heun, PatchMotion::Smooth);
  };

  // The paper's rule (--distorted fade): the patch is lost.
  o.distorted = Distorted::Fade;
  Patch lost = *built;
  EXPECT_EQ(advect(lost, next), AdvectResult::CentreLost);

  // With recut: the centre moves onto the sunk surface and the patch is cut
  // again there, with its identity.
  o.distorted = Distorted::Recut;
  Patch moved = *built;
  ASSERT_EQ(advect(moved, next), AdvectResult::CentreMoved);
  EXPECT_TRUE(moved.centre.point.valid());
  EXPECT_NEAR(moved.centre.point.position.z(), -depth, 1e-9);
  const std::optional<Patch> cut = recut_patch(moved, next, o, 1, 2, 0.25 * o.d());
  ASSERT_TRUE(cut);
  EXPECT_EQ(cut->id, built->id);

  // A patch that has sunk entirely is lost even with recut.
  const FrameMesh gone = sunk(0.3);
  const SurfaceIndex far(gone);
  Patch over = *built;
  EXPECT_EQ(advect(over, far), AdvectResult::CentreLost);
}

TEST(ProjectionSlack, AFastSheetWhoseVelocityOverpredictsItsNormalMotionKeepsItsPatch) {
  // A sheet rising at w with a tangential drift u, whose next frame lies at
  // 0.7 of w·dt (the solver's velocity over-predicts the normal motion by
  // 30 %, as on the dam break's fast sheets): advected points land 1.2 mpt
  // beyond it. mpt alone loses the patch; the slack keeps it, carried by
  // u·dt along the sheet.
  TrackingOptions o = TrackingOptions{}.resolved(1.0);
  o.radius = 0.15;
  const double dt = 1.0 / 24, rise = 4.0 * o.mpt(), u = 0.02 / dt;
  const Vec3 velocity(u, 0.0, rise / dt);
  const FrameMesh before = test::flat_grid(40, 1.0, 0.0, 0.0, 0.0, [&](const Vec3&) { return velocity; });
  const FrameMesh after = test::flat_grid(40, 1.0, 0.7 * rise, 0.0, 0.0, [&](const Vec3&) { return velocity; });
  const SurfaceIndex previous(before), next(after);
  SurfaceSample c;
  c.point = previous.closest_point(Vec3(0.5, 0.5, 0));
  c.normal = previous.normal_at(c.point);
  const std::optional<Patch> built = build_patch(previous, c, o, 7, 1, 1, 0.25 * o.d());
  ASSERT_TRUE(built);
  const auto advect = [&](Patch& patch, const SurfaceIndex& to) {
    return advect_patch(patch, previous, to, dt, o, Advection::Euler, PatchMotion::Smooth);
  };
  EXPECT_NEAR(projection_tolerance(c.point, c.normal, c.point.position + velocity * dt, o),
              o.mpt() + o.projection_slack * rise, 1e-12);

  o.projection_slack = 0.0;  // the paper: beyond mpt, lost
  Patch paper = *built;
  EXPECT_EQ(advect(paper, next), AdvectResult::CentreLost);

  o.projection_slack = TrackingOptions{}.projection_slack;
  ASSERT_GE(o.projection_slack * rise + o.mpt(), 1.2 * o.mpt());
  Patch kept = *built;
  ASSERT_EQ(advect(kept, next), AdvectResult::Kept);
  EXPECT_EQ(kept.num_vertices(), built->num_vertices());
  EXPECT_NEAR(kept.centre.point.position.x(), 0.5 + u * dt, 1e-9);
  EXPECT_NEAR(kept.centre.point.position.z(), 0.7 * rise, 1e-9);

  // Motion along the sheet earns no slack: the same sheet drifting at u
  // alone while the next frame jumps by 2 mpt has left the liquid.
  const FrameMesh drift = test::flat_grid(40, 1.0, 0.0, 0.0, 0.0, [&](const Vec3&) { return Vec3(u, 0, 0); });
  const FrameMesh jumped =
      test::flat_grid(40, 1.0, 2.0 * o.mpt(), 0.0, 0.0, [&](const Vec3&) { return Vec3(u, 0, 0); });
  const SurfaceIndex drifting(drift), away(jumped);
  c.point = drifting.closest_point(Vec3(0.5, 0.5, 0));
  c.normal = drifting.normal_at(c.point);
  std::optional<Patch> gone = build_patch(drifting, c, o, 7, 1, 1, 0.25 * o.d());
  ASSERT_TRUE(gone);
  EXPECT_EQ(advect_patch(*gone, drifting, away, dt, o, Advection::Euler, PatchMotion::Smooth),
            AdvectResult::CentreLost);
}

TEST(Recut, APatchWhoseCentreLeavesThroughAnOutflowFadesOutOnTheRim) {
  // Liquid flowing out through the open edge x = 1: a patch whose centre has
  // left through it stays on the rim to fade out, whether the centre went
  // past the edge by more than mpt or by less (then, taken back onto the rim
  // as a near miss, it would stay there for good), and its motion is the
  // liquid's, which sets the pace of the fade.
  TrackingOptions o = TrackingOptions{}.resolved(1.0);
  o.radius = 0.15;
  o.distorted = Distorted::Recut;
  for (const double beyond : {2.0 * o.mpt(), 0.5 * o.mpt()}) {
    const double shift = 0.05 + beyond;  // the centre starts 0.05 inside the edge
    const FrameMesh flow = test::flat_grid(40, 1.0, 0.0, 0.0, 0.0, [&](const Vec3&) { return Vec3(24 * shift, 0, 0); });
    const SurfaceIndex previous(flow), next(flow);
    SurfaceSample c;
    c.point = previous.closest_point(Vec3(0.95, 0.5, 0));
    c.normal = previous.normal_at(c.point);
    std::optional<Patch> patch = build_patch(previous, c, o, 7, 1, 1, 0.25 * o.d());
    ASSERT_TRUE(patch);
    EXPECT_EQ(advect_patch(*patch, previous, next, 1.0 / 24, o, Advection::Euler, PatchMotion::Smooth),
              AdvectResult::LeftThroughRim)
        << beyond;
    EXPECT_NEAR(patch->centre.point.position.x(), 1.0, 1e-9) << beyond;
    EXPECT_NEAR(patch->motion, shift / o.d(), 1e-6) << beyond;
  }
}

TEST(Rim, AnOutlineThatMovesWithTheLiquidKeepsItsRimAndAnInflowRimLetsGo) {
  // An open sheet spreading along x at 6 % per frame, its velocity sampled
  // at the frame's instant (k·x, as analytic scenes store it): Euler lags
  // the moving rim by ½·k²x·dt² a frame. A patch on the rim keeps its rim
  // vertices and its centre on the rim, frame after frame.
  const double k = 1.5, dt = 1.0 / 24;
  auto sheet = [&](double width) {
    FrameMesh m = test::flat_grid(24, 1.2, 0.0, -0.6, -0.6);
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
      m.positions[v].x() *= width;
      m.velocities[v] = Vec3(k * m.positions[v].x(), 0.0, 0.0);
    }
    return m;
  };
  TrackingOptions o = TrackingOptions{}.resolved(1.0);
  o.radius = 0.15;
  std::vector<FrameMesh> frames;
  for (int f = 0; f < 7; ++f) frames.push_back(sheet(std::exp(k * dt * f)));
  SurfaceIndex first(frames[0]);
  SurfaceSample c;
  c.point = first.closest_point(Vec3(0.6, 0.05, 0));
  c.normal = first.normal_at(c.point);
  std::optional<Patch> patch = build_patch(first, c, o, 7, 1, 1, 0.25 * o.d());
  ASSERT_TRUE(patch);
  int on_rim = 0;
  for (int f = 1; f < 7; ++f) {
    const SurfaceIndex previous(frames[f - 1]), next(frames[f]);
    std::vector<char> was(patch->num_vertices());
    for (std::size_t v = 0; v < was.size(); ++v) was[v] = previous.on_boundary(patch->projections[v]);
    ASSERT_NE(advect_patch(*patch, previous, next, dt, o, Advection::Euler, PatchMotion::Smooth),
              AdvectResult::CentreLost);
    ASSERT_EQ(patch->num_vertices(), was.size());  // nothing lost past the rim
    const double rim = 0.6 * std::exp(k * dt * f);
    EXPECT_NEAR(patch->centre.point.position.x(), rim, 1e-9) << f;
    for (std::size_t v = 0; v < was.size(); ++v) {
      if (!was[v] || std::abs(patch->positions[v].y()) > 0.59) continue;  // the corners are another matter
      ++on_rim;
      EXPECT_NEAR(patch->positions[v].x(), rim, 1e-9) << f;
    }
  }
  EXPECT_GT(on_rim, 12);

  // Liquid entering through the still rim x = 0: the rim stays, the
  // liquid moves away from it, and so do the patch's rim vertices.
  const Vec3 inflow(0.5, 0, 0);
  const FrameMesh still = test::flat_grid(40, 1.0, 0.0, 0.0, 0.0, [&](const Vec3&) { return inflow; });
  const SurfaceIndex surface(still);
  c.point = surface.closest_point(Vec3(0.0, 0.5, 0));
  c.normal = surface.normal_at(c.point);
  std::optional<Patch> entering = build_patch(surface, c, o, 7, 1, 1, 0.25 * o.d());
  ASSERT_TRUE(entering);
  const Patch before = *entering;
  ASSERT_NE(advect_patch(*entering, surface, surface, dt, o, Advection::Euler, PatchMotion::Smooth),
            AdvectResult::CentreLost);
  ASSERT_EQ(entering->num_vertices(), before.num_vertices());
  EXPECT_NEAR((entering->centre.point.position - before.centre.point.position - inflow * dt).norm(), 0.0, 1e-9);
  for (std::size_t v = 0; v < before.num_vertices(); ++v)
    EXPECT_NEAR((entering->positions[v] - before.positions[v] - inflow * dt).norm(), 0.0, 1e-9);
}

TEST(Recut, ACrushedPatchIsCutAgainNotReplaced) {
  // The liquid converges towards x = 0 for 16 frames (e⁻² of its width: a
  // Sorkine distortion of 7.4, beyond what relaxation takes out). The paper
  // fades the crushed patches out and seeds new ones; recut patches stay,
  // cut again in place, and the surface stays covered.
  const CloseRun fade = converging_plane(8, 16, 16, 3.0, Distorted::Fade);
  const CloseRun recut = converging_plane(8, 16, 16, 3.0, Distorted::Recut);
  EXPECT_GT(fade.distorted, 5);
  EXPECT_EQ(fade.recut, 0);
  EXPECT_EQ(recut.distorted, 0);
  EXPECT_GT(recut.recut, 5);
  EXPECT_EQ(recut.uncovered_max, 0.0);
  // Every recut patch (as its recut frame shows) is counted once, under the
  // rule that found it distorted (here the squeeze, quality, never a rule
  // that does not recut), or as regrown over the strip the converging
  // liquid bares along the window's edges.
  EXPECT_EQ(recut.recut + recut.regrown, recut.recut_seen);
  EXPECT_EQ(std::accumulate(recut.recut_causes.begin(), recut.recut_causes.end(), 0), recut.recut);
  EXPECT_GT(recut.recut_causes[static_cast<int>(RetireCause::Quality)], recut.recut / 2);
  EXPECT_EQ(recut.recut_causes[static_cast<int>(RetireCause::None)], 0);
  EXPECT_EQ(recut.recut_causes[static_cast<int>(RetireCause::TooClose)], 0);
  StepReport step;
  step.recut_causes[static_cast<int>(RetireCause::Quality)] = 4;
  step.recut_causes[static_cast<int>(RetireCause::CentreLost)] = 1;
  const auto names = recut_counts(step);
  ASSERT_EQ(names.size(), 5u);  // centre lost, vertices lost, split, flipped, quality
  EXPECT_EQ(names[0], std::make_pair(std::string("recut_centre_lost"), 1.0));
  EXPECT_EQ(names[4], std::make_pair(std::string("recut_quality"), 4.0));
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
