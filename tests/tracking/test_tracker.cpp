// The tracker (tracking/tracker.h): the states on known motions and the
// generated scenes, coverage, determinism over thread counts, state files.
#include <gtest/gtest.h>

#include <algorithm>

#include <oneapi/tbb/global_control.h>

#include "fluidtex/geometry/distortion.h"
#include "fluidtex/scenes/scenes.h"
#include "fluidtex/tracking/fading.h"
#include "fluidtex/tracking/patch.h"
#include "fluidtex/tracking/patch_builder.h"
#include "fluidtex/tracking/patch_coverage.h"
#include "fluidtex/tracking/tracker.h"
#include "fluidtex/util/error.h"
#include "mesh_fixtures.h"
#include "test_util.h"

namespace fluidtex {
namespace {

// --- Tracker ---------------------------------------------------------------------

std::shared_ptr<FrameMesh> rotating_grid(double omega) {
  return std::make_shared<FrameMesh>(test::flat_grid(
      40, 1.0, 0.0, -0.5, -0.5, [omega](const Vec3& p) { return Vec3(-omega * p.y(), omega * p.x(), 0); }));
}

TrackerSettings small_settings() {
  TrackerSettings s;
  s.tracking.radius = 0.12;
  s.tracking.fade_frames = 8;
  s.seed = 5;
  return s;
}

TEST(Tracker, ZeroVelocityKeepsTheFirstDistribution) {
  Tracker t(small_settings());
  const StepReport first = t.step(rotating_grid(0.0), 1, 1.0 / 24);
  EXPECT_GT(first.created, 10);
  EXPECT_EQ(first.counts.active, first.created);
  for (int f = 2; f <= 5; ++f) {
    const StepReport r = t.step(rotating_grid(0.0), f, 1.0 / 24);
    EXPECT_EQ(r.created, 0);
    EXPECT_EQ(r.removed, 0);
    EXPECT_EQ(r.counts.active, first.created);
  }
  for (const Patch& p : t.patches()) {
    EXPECT_NEAR(p.max_distortion, 1.0, 1e-6);
    EXPECT_EQ(p.kt, 1.0);
  }
}

TEST(Tracker, ConstantVelocityTranslatesPatchesExactly) {
  // A large plane translating: patch vertices move by exactly v·dt.
  const Vec3 v(0.3, -0.12, 0);
  auto plane = [&]() {
    return std::make_shared<FrameMesh>(test::flat_grid(30, 3.0, 0.0, -1.5, -1.5, [&](const Vec3&) { return v; }));
  };
  TrackerSettings s = small_settings();
  s.tracking.radius = 0.3;
  // The window is fixed: the strip the liquid bares at its upstream edge
  // would be covered by recutting the patches next to it.
  s.tracking.gap_fill = GapFill::Seed;
  Tracker t(s);
  t.step(plane(), 1, 0.1);
  const Patch before = t.patches().front();
  t.step(plane(), 2, 0.1);
  const Patch& after = t.patches().front();
  ASSERT_EQ(after.id, before.id);
  EXPECT_NEAR((after.centre.point.position - before.centre.point.position - 0.1 * v).norm(), 0.0, 1e-12);
  ASSERT_EQ(after.num_vertices(), before.num_vertices());
  for (std::size_t i = 0; i < after.num_vertices(); ++i) {
    EXPECT_NEAR((after.positions[i] - before.positions[i] - 0.1 * v).norm(), 0.0, 1e-12);
  }
  EXPECT_NEAR(after.max_distortion, 1.0, 1e-9);
}

TEST(Tracker, RotationGoesThroughTheStates) {
  // The paper's states: a distorted patch fades out rather than being recut.
  TrackerSettings s = small_settings();
  s.tracking.distorted = Distorted::Fade;
  Tracker t(s);
  bool saw_fading_in = false, saw_close = false, saw_distorted = false;
  int removed = 0;
  for (int f = 1; f <= 40; ++f) {
    const StepReport r = t.step(rotating_grid(1.5), f, 1.0 / 24);
    saw_fading_in |= r.counts.fading_in > 0;
    saw_close |= r.counts.fading_out_close > 0;
    saw_distorted |= r.counts.fading_out_distorted > 0;
    removed += r.removed;
    for (const Patch& p : t.patches()) {
      EXPECT_GE(p.kt, 0.0);
      EXPECT_LE(p.kt, 1.0);
      if (p.state == DiskState::Active) EXPECT_EQ(p.kt, 1.0);
    }
  }
  EXPECT_TRUE(saw_fading_in);
  EXPECT_TRUE(saw_close || saw_distorted);
  EXPECT_GT(removed, 0);
}

/// Share of the tracker's current surface that no patch covers, tested at
/// points `spacing` apart.
double uncovered_area(const Tracker& t, double spacing) {
  const PatchCoverage coverage(t.patches(), t.settings().tracking.mpt());
  return uncovered_area_fraction(*t.surface(), coverage, spacing);
}

TEST(Tracker, GeneratedScenesGoThroughTheStatesAndStayCovered) {
  // The rotation keeps its patches; the drop, through its contact (frame ~6
  // of 12), replaces some: patches fade in, fade out and are removed, and
  // K_t follows Eq. 6 (the paper's states: distorted patches fade out).
  SceneOptions so;
  so.resolution = 20;
  so.frames = 12;
  for (const char* scene : {"rotation", "drop"}) {
    SCOPED_TRACE(scene);
    TrackerSettings s;
    s.tracking.distorted = Distorted::Fade;
    Tracker t(s);
    int created_later = 0, removed = 0, fading_out = 0;
    for (int f = 1; f <= so.frames; ++f) {
      const StepReport r = t.step(std::make_shared<FrameMesh>(make_scene_frame(scene, f, so)), f, 1.0 / so.fps);
      if (f > 1) created_later += r.created;
      removed += r.removed;
      fading_out += r.counts.fading_out_distorted + r.counts.fading_out_close;
      for (const Patch& p : t.patches()) {
        ASSERT_GE(p.kt, 0.0);
        ASSERT_LE(p.kt, 1.0);
        if (p.state == DiskState::Active) ASSERT_EQ(p.kt, 1.0);
        if (p.state == DiskState::FadingIn) ASSERT_LT(p.kt, 1.0);
      }
      EXPECT_LT(uncovered_area(t, t.coverage_spacing()), 1e-3) << "frame " << f;
    }
    if (std::string(scene) == "rotation") {
      EXPECT_EQ(removed, 0);
    } else {
      EXPECT_GT(created_later, 0);
      EXPECT_GT(fading_out, 0);
      EXPECT_GT(removed, 0);
    }
  }
}

/// Droplets smaller than the disk, as splashes shed them: a pool with three
/// coarse blobs of radius 0.1–0.3 d above it. The plane test cuts a patch on
/// such a blob down to a few triangles whose vertices all lie on its border
/// (d_V = 0: Eq. 4 gives it no weight anywhere); its coverage tail must still
/// cover the blob, whatever the frame.
TEST(Tracker, DropletsSmallerThanTheDiskAreCovered) {
  FrameMesh mesh = test::flat_grid(24, 4.0);
  test::append(mesh, test::uv_sphere(3, 5, 0.1, Vec3(1.0, 1.0, 0.5)));
  test::append(mesh, test::uv_sphere(4, 6, 0.2, Vec3(2.0, 2.5, 0.6)));
  test::append(mesh, test::uv_sphere(3, 4, 0.3, Vec3(3.0, 1.2, 0.8)));
  TrackerSettings settings;
  settings.tracking.radius = 1.0;
  Tracker t(settings);
  for (int f = 1; f <= 3; ++f) {
    t.step(std::make_shared<FrameMesh>(mesh), f, 1.0 / 24.0);
    EXPECT_EQ(uncovered_area(t, t.coverage_spacing()), 0.0) << "frame " << f;
  }
}

/// Faces several disks wide (a coarse cache, or a wall of the tank meshed
/// with a few large triangles): coverage is tested at points d/4 apart
/// (kCoverageSpacing), so no bare sliver hides inside a face whose centre is covered. At
/// half that spacing, gaps narrower than the samples may show (synthesis
/// gives them a patch's margin), a tiny share of the area.
TEST(Tracker, CoarseFacesAreCoveredInside) {
  const FrameMesh mesh =
      test::flat_grid(3, 3.0, 0.0, 0.0, 0.0, [](const Vec3& p) { return Vec3(0.3 * p.y(), 0.0, 0.0); });
  TrackerSettings settings;
  settings.tracking.radius = 0.25;
  Tracker t(settings);
  for (int f = 1; f <= 4; ++f) {
    t.step(std::make_shared<FrameMesh>(mesh), f, 1.0 / 24.0);
    EXPECT_EQ(uncovered_area(t, t.coverage_spacing()), 0.0) << "frame " << f;
    EXPECT_LT(uncovered_area(t, 0.5 * t.coverage_spacing()), 2e-4) << "frame " << f;
  }
}

std::string run_and_save(int threads, const std::string& path) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  Tracker t(small_settings());
  for (int f = 1; f <= 12; ++f) t.step(rotating_grid(1.5), f, 1.0 / 24);
  t.save(path);
  return test::read_file(path);
}

TEST(Tracker, IdenticalForAnyThreadCount) {
  test::TempDir dir;
  const std::string one = run_and_save(1, dir.file("a.bin"));
  const std::string two = run_and_save(2, dir.file("b.bin"));
  EXPECT_GT(one.size(), 1000u);
  EXPECT_TRUE(one == two);
}

TEST(Tracker, StateRoundTripContinuesExactly) {
  test::TempDir dir;
  Tracker a(small_settings());
  std::shared_ptr<FrameMesh> mesh;
  for (int f = 1; f <= 6; ++f) a.step(mesh = rotating_grid(1.5), f, 1.0 / 24);
  a.save(dir.file("s6.bin"));
  Tracker b = Tracker::load(dir.file("s6.bin"), rotating_grid(1.5));
  b.save(dir.file("s6b.bin"));
  EXPECT_EQ(test::read_file(dir.file("s6.bin")), test::read_file(dir.file("s6b.bin")));
  EXPECT_EQ(b.frame(), 6);
  for (int f = 7; f <= 9; ++f) {
    a.step(rotating_grid(1.5), f, 1.0 / 24);
    b.step(rotating_grid(1.5), f, 1.0 / 24);
  }
  a.save(dir.file("a9.bin"));
  b.save(dir.file("b9.bin"));
  EXPECT_EQ(test::read_file(dir.file("a9.bin")), test::read_file(dir.file("b9.bin")));
}

TEST(Tracker, StateFileErrors) {
  test::TempDir dir;
  Tracker a(small_settings());
  a.step(rotating_grid(1.0), 1, 1.0 / 24);
  a.save(dir.file("s.bin"));
  EXPECT_THROW(Tracker::load(dir.file("s.bin"), rotating_grid(2.0)), InputError);  // other velocities
  const std::string bytes = test::read_file(dir.file("s.bin"));
  // Cut anywhere, or one byte damaged anywhere (the checksum catches what
  // the structure does not): refused, never loaded, never a crash.
  for (std::size_t at = 0; at < bytes.size(); at += std::max<std::size_t>(1, bytes.size() / 61)) {
    test::write_file(dir.path() / "t.bin", bytes.substr(0, at));
    EXPECT_THROW(Tracker::load(dir.file("t.bin"), rotating_grid(1.0)), InputError) << "cut at " << at;
    std::string bad = bytes;
    bad[at] = static_cast<char>(bad[at] ^ 0x5a);
    test::write_file(dir.path() / "e.bin", bad);
    EXPECT_THROW(Tracker::load(dir.file("e.bin"), rotating_grid(1.0)), InputError) << "flip at " << at;
  }
  test::write_file(dir.path() / "x.bin", bytes + "x");
  EXPECT_THROW(Tracker::load(dir.file("x.bin"), rotating_grid(1.0)), InputError);
  test::write_file(dir.path() / "u.bin", "hello");
  EXPECT_THROW(Tracker::load(dir.file("u.bin"), rotating_grid(1.0)), InputError);
  EXPECT_THROW(Tracker::load(dir.file("missing.bin"), rotating_grid(1.0)), InputError);
}

}  // namespace
}  // namespace fluidtex
