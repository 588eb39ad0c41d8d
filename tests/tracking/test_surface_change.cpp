// Where the liquid makes and destroys surface (surface_change.h).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numeric>

#include "fluidtex/tracking/surface_change.h"
#include "fluidtex/tracking/tracker.h"
#include "mesh_fixtures.h"

namespace fluidtex {
namespace {

constexpr double kDt = 1.0 / 24.0;
constexpr double kRadius = 0.1;

Vec3 centroid(const FrameMesh& m, std::size_t f) {
  const Tri& t = m.triangles[f];
  return (m.positions[t[0]] + m.positions[t[1]] + m.positions[t[2]]) / 3.0;
}

TEST(SurfaceChange, ASurfaceCarriedRigidlyKeepsItsArea) {
  // A sheet translating with its velocity: the next frame is the same sheet,
  // moved by v·dt and meshed more finely (meshes are independent per frame).
  const Vec3 v(0.6, 0.3, 0.0);
  const FrameMesh a = test::flat_grid(40, 1.0, 0.0, 0.0, 0.0, [&](const Vec3&) { return v; });
  const FrameMesh b = test::flat_grid(47, 1.0, 0.0, v.x() * kDt, v.y() * kDt, [&](const Vec3&) { return v; });
  const SurfaceIndex sa(a), sb(b);
  const SurfaceChange change = measure_surface_change(sa, sb, kDt, 1.0, kRadius, 0.5);
  ASSERT_EQ(change.rate.size(), b.triangles.size());
  double worst = 0.0;
  for (std::size_t f = 0; f < b.triangles.size(); ++f) {
    const Vec3 c = centroid(b, f) - Vec3(v.x() * kDt, v.y() * kDt, 0.0);
    if (c.x() > kRadius && c.x() < 1 - kRadius && c.y() > kRadius && c.y() < 1 - kRadius)
      worst = std::max(worst, std::abs(static_cast<double>(change.rate[f])));
  }
  EXPECT_LT(worst, 0.01);  // within the "kept" class everywhere inside
}

TEST(SurfaceChange, AStreamThroughAFixedWindowMakesSurfaceAtItsInflowAndDestroysItAtItsOutflow) {
  // Liquid crossing [0, 1]² along +x at 1 unit/s: the window stays, so
  // surface appears along x = 0 and vanishes along x = 1.
  auto flow = [](const Vec3&) { return Vec3(1.0, 0.0, 0.0); };
  const FrameMesh a = test::flat_grid(40, 1.0, 0.0, 0.0, 0.0, flow);
  const FrameMesh b = test::flat_grid(43, 1.0, 0.0, 0.0, 0.0, flow);
  const SurfaceIndex sa(a), sb(b);
  const SurfaceChange change = measure_surface_change(sa, sb, kDt, 1.0, kRadius, 0.5);
  double inflow = 0.0, outflow = 0.0, middle = 0.0;
  for (std::size_t f = 0; f < b.triangles.size(); ++f) {
    const Vec3 c = centroid(b, f);
    if (c.y() < kRadius || c.y() > 1 - kRadius) continue;
    const double r = change.rate[f];
    if (c.x() < 0.03) inflow = std::max(inflow, r);
    if (c.x() > 0.97) outflow = std::min(outflow, r);
    if (c.x() > 2 * kRadius && c.x() < 1 - 2 * kRadius) middle = std::max(middle, std::abs(r));
  }
  EXPECT_GT(inflow, kChangeClassEdges.back());    // a strong source
  EXPECT_LT(outflow, kChangeClassEdges.front());  // a strong sink
  EXPECT_LT(middle, 0.005);
  EXPECT_EQ(change_class(inflow), kChangeClasses - 1);
  EXPECT_EQ(change_class(outflow), 0);
  EXPECT_EQ(change_class(0.0), 2);
  EXPECT_STREQ(change_class_name(change_class(0.0)), "kept");
  // Twice the step over two frame steps is the same change per frame.
  const SurfaceChange two = measure_surface_change(sa, sb, 2 * kDt, 2.0, kRadius, 0.5);
  const std::size_t mid = b.triangles.size() / 2;
  EXPECT_NEAR(two.rate[mid], change.rate[mid], 0.005);
}

TEST(SurfaceChange, TheTrackerCountsPatchesBirthsAndRemovalsWhereTheSurfaceIsMadeAndDestroyed) {
  auto flow = [](const Vec3&) { return Vec3(1.5, 0.0, 0.0); };
  TrackerSettings settings;
  settings.tracking.radius = kRadius;
  Tracker tracker(settings);
  const StepReport first =
      tracker.step(std::make_shared<const FrameMesh>(test::flat_grid(30, 1.0, 0.0, 0.0, 0.0, flow)), 1, kDt);
  EXPECT_FALSE(first.change.measured());
  ChangeTally sum;
  const double strip = 1.5 * kDt;  // the area that enters and leaves per frame
  for (int frame = 2; frame <= 12; ++frame) {
    const auto mesh = std::make_shared<const FrameMesh>(test::flat_grid(30 + frame % 3, 1.0, 0.0, 0.0, 0.0, flow));
    const StepReport step = tracker.step(mesh, frame, kDt);
    ASSERT_TRUE(step.change.measured());
    const double area = std::accumulate(step.change.area.begin(), step.change.area.end(), 0.0);
    EXPECT_NEAR(area, 1.0, 1e-9);
    EXPECT_EQ(std::accumulate(step.change.patches.begin(), step.change.patches.end(), 0),
              static_cast<int>(tracker.patches().size()));
    EXPECT_EQ(std::accumulate(step.change.births.begin(), step.change.births.end(), 0),
              static_cast<int>(step.births.size()));
    EXPECT_EQ(std::accumulate(step.change.removals.begin(), step.change.removals.end(), 0),
              static_cast<int>(step.removals.size()));
    EXPECT_NEAR(step.change.made, strip, 0.25 * strip);
    // The outflow piles what it destroys onto its rim, narrower than the
    // ball of radius d the change is measured in: the loss reads smaller.
    EXPECT_GT(step.change.lost, 0.5 * strip);
    EXPECT_LT(step.change.lost, 1.25 * strip);
    for (int c = 0; c < kChangeClasses; ++c)
      sum.births[c] += step.change.births[c], sum.removals[c] += step.change.removals[c];
  }
  // The stream makes surface along its inflow, where disks are born, and
  // removes it along its outflow, where patches leave.
  EXPECT_GT(sum.births[kChangeClasses - 1], 0);
  EXPECT_GT(sum.removals[0], sum.removals[kChangeClasses - 1]);
  const std::vector<std::pair<std::string, double>> named = sum.named();
  ASSERT_EQ(named.size(), 4u * kChangeClasses + 2);
  EXPECT_EQ(named.front().first, "change_area_sink_fast");
  EXPECT_EQ(named[4 * kChangeClasses - 1].first, "change_removals_source_fast");
  EXPECT_EQ(named.back().first, "change_lost_area");
}

}  // namespace
}  // namespace fluidtex
