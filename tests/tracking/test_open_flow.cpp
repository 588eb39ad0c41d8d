// Liquid that enters and leaves: the generated streams (scenes.h), whose
// surface is made at the inflow edge x = -1.5 and destroyed at the outflow
// edge x = 1.5 every frame, and kept everywhere else.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include "fluidtex/scenes/scenes.h"
#include "fluidtex/tracking/tracker.h"

namespace fluidtex {
namespace {

constexpr double kEdge = 1.5;  // the streams' window is [-1.5, 1.5] in x

struct StreamRun {
  double d = 0.0;
  std::vector<int> live;                                 // patches per frame
  std::vector<std::pair<int, double>> births, removals;  // (frame, x)
};

StreamRun track_stream(const std::string& scene, int frames, const TrackingOptions& method = {}) {
  SceneOptions so;
  so.frames = frames;
  so.resolution = 48;
  const auto mesh = std::make_shared<const FrameMesh>(make_scene_frame(scene, 1, so));
  TrackerSettings settings;
  settings.method = method;
  Tracker tracker(settings);
  StreamRun run;
  for (int frame = 1; frame <= frames; ++frame) {
    const StepReport step = tracker.step(mesh, frame, 1.0 / so.fps);  // the window is the same sheet every frame
    run.live.push_back(static_cast<int>(tracker.patches().size()));
    if (frame == 1) continue;
    for (const Vec3& b : step.births) run.births.emplace_back(frame, b.x());
    for (const Vec3& r : step.removals) run.removals.emplace_back(frame, r.x());
  }
  run.d = tracker.settings().method.d();
  return run;
}

/// The share of `events` after frame `settle` that lie within 1.5 d of the
/// edge x = `edge` (on its inner side).
double share_near(const std::vector<std::pair<int, double>>& events, int settle, double edge, double d) {
  int near = 0, all = 0;
  for (auto [frame, x] : events) {
    if (frame <= settle) continue;
    ++all;
    near += std::abs(x - edge) < 1.5 * d;
  }
  return all ? static_cast<double>(near) / all : 1.0;
}

/// A steady count: within ±5 % of its mean over the second half of the run,
/// and never above 1.3 times the first frame's (the window keeps its area).
void expect_steady(const std::vector<int>& live, const std::string& scene) {
  const std::vector<int> late(live.begin() + static_cast<std::ptrdiff_t>(live.size() / 2), live.end());
  const double mean = std::accumulate(late.begin(), late.end(), 0.0) / static_cast<double>(late.size());
  for (int n : late) EXPECT_NEAR(n, mean, 0.05 * mean) << scene;
  EXPECT_LE(*std::max_element(live.begin(), live.end()), 1.3 * live.front()) << scene;
}

TEST(OpenFlow, ARigidStreamGetsItsPatchesAtTheInflowAndLosesThemAtTheOutflow) {
  const int frames = 120;
  const StreamRun run = track_stream("stream", frames);
  const int settle = 2 * TrackingOptions{}.fade_frames;
  // Where the liquid moves rigidly, disks are born only where it enters and
  // leave only where it leaves. A patch whose centre leaves through the
  // outflow fades out on the rim; what it covered until then, the next
  // one's cut does not always reach, and a disk is born there now and then
  // (and leaves at once).
  const double at_inflow = share_near(run.births, settle, -kEdge, run.d);
  const double at_outflow = share_near(run.births, settle, kEdge, run.d);
  EXPECT_DOUBLE_EQ(at_inflow + at_outflow, 1.0);
  EXPECT_GT(at_inflow, 0.9);
  EXPECT_DOUBLE_EQ(share_near(run.removals, settle, kEdge, run.d), 1.0);
  expect_steady(run.live, "stream");
}

TEST(OpenFlow, LargerDisksDoNotPileUpOnTheOutflowRim) {
  // At 1.5 times the default radius mpt exceeds the liquid's motion a frame
  // (0.05): a centre carried past the outflow rim lands within mpt of it.
  // It leaves all the same (it fades out on the rim) instead of staying on
  // the rim while the liquid flows on, which piled up disks there.
  const TrackingOptions defaults = TrackingOptions{}.resolved(std::hypot(3.0, 1.0));
  TrackingOptions method;
  method.radius = 1.5 * defaults.d();
  ASSERT_GT(TrackingOptions(method).resolved(std::hypot(3.0, 1.0)).mpt(), 1.2 / 24.0);
  const StreamRun run = track_stream("stream", 120, method);
  expect_steady(run.live, "stream at 1.5 d");
  EXPECT_DOUBLE_EQ(share_near(run.removals, 2 * TrackingOptions{}.fade_frames, kEdge, run.d), 1.0);
}

TEST(OpenFlow, AStreamAroundARockKeepsASteadyCount) {
  const int frames = 120;
  const StreamRun run = track_stream("stream-rock", frames);
  const int settle = 2 * TrackingOptions{}.fade_frames;
  // The rock squeezes the liquid along the flow before it and stretches it
  // behind: the kill distance and the gaps it leaves add some removals and
  // births around it; most are still at the edges.
  EXPECT_GT(share_near(run.births, settle, -kEdge, run.d), 2.0 / 3.0);
  EXPECT_GT(share_near(run.removals, settle, kEdge, run.d), 2.0 / 3.0);
  expect_steady(run.live, "stream-rock");
}

TEST(OpenFlow, WithoutTheGapFillAndTheSinkRuleThePatchesPileUpInAStream) {
  // Without the gap fill and the sink rule, every frame seeds a row of
  // disks along the inflow beside the patches that just left it, and the
  // count climbs all through the run.
  TrackingOptions paper;
  paper.gap_fill = GapFill::Seed;
  paper.sink = Sink::Keep;
  const StreamRun run = track_stream("stream", 60, paper);
  EXPECT_GT(run.live.back(), 1.5 * run.live.front());
}

}  // namespace
}  // namespace fluidtex
