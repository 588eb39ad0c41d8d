// The tracker on short cuts of the real liquid caches (../shared/realdata):
// patches kept, churn bounded, the surface covered. Each test is reported
// as skipped, with the reason, where the caches are absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <set>
#include <string>

#include "fluidtex/io/sequence.h"
#include "fluidtex/tracking/patch_coverage.h"
#include "fluidtex/tracking/tracker.h"
#include "test_util.h"

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

}  // namespace
}  // namespace fluidtex
