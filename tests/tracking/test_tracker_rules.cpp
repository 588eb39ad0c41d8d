// The tracker's rules over many frames on analytic liquids: the kill frames
// (a compression the liquid undoes), the sink rule, the birth margin, and
// recut against fade for patches the liquid crushes.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <string>
#include <utility>

#include "fluidtex/tracking/patch_coverage.h"
#include "fluidtex/tracking/tracker.h"
#include "mesh_fixtures.h"

namespace fluidtex {
namespace {

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

}  // namespace
}  // namespace fluidtex
