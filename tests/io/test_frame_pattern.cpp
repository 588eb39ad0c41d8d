#include <gtest/gtest.h>

#include <algorithm>

#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/io/sequence.h"
#include "fluidtex/scenes/scenes.h"
#include "fluidtex/tracking/options.h"
#include "fluidtex/util/error.h"
#include "mesh_fixtures.h"
#include "test_util.h"

namespace fluidtex {
namespace {

TEST(FramePattern, HashesPadToTheirCount) {
  FramePattern p("out/mesh.####.ply");
  EXPECT_EQ(p.width(), 4);
  EXPECT_EQ(p.path(7), "out/mesh.0007.ply");
  EXPECT_EQ(p.path(12345), "out/mesh.12345.ply");
  EXPECT_EQ(FramePattern("a.#.ply").path(42), "a.42.ply");
}

TEST(FramePattern, PrintfStyle) {
  EXPECT_EQ(FramePattern("f.%04d.ply").path(3), "f.0003.ply");
  EXPECT_EQ(FramePattern("f.%d.ply").path(3), "f.3.ply");
  EXPECT_EQ(FramePattern("f_%3d.obj").path(3), "f_003.obj");
}

TEST(FramePattern, HoudiniStyle) {
  EXPECT_EQ(FramePattern("geo/fluid.$F4.ply").path(12), "geo/fluid.0012.ply");
  EXPECT_EQ(FramePattern("fluid.$F.ply").path(12), "fluid.12.ply");
  EXPECT_EQ(FramePattern("fluid.$F.ply").prefix(), "fluid.");
  EXPECT_EQ(FramePattern("fluid.$F.ply").suffix(), ".ply");
}

TEST(FramePattern, NegativeFrames) { EXPECT_EQ(FramePattern("f.####.ply").path(-3), "f.-0003.ply"); }

TEST(FramePattern, RejectsPatternsWithoutOrWithTwoTokens) {
  EXPECT_THROW(FramePattern("mesh.ply"), InputError);
  EXPECT_THROW(FramePattern("mesh.####.%04d.ply"), InputError);
  EXPECT_THROW(FramePattern("dir$F/mesh.ply"), InputError);
  try {
    FramePattern("mesh.ply");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mesh.ply"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("####"), std::string::npos);
  }
}

TEST(FramePattern, DiscoversOnlyMatchingFiles) {
  test::TempDir dir;
  for (const char* name : {"m.0001.ply", "m.0002.ply", "m.0010.ply", "m.12345.ply", "m.001.ply", "m.00002.ply",
                           "m.0003.obj", "n.0004.ply", "m.00a5.ply", "m.0006.ply.tmp"}) {
    test::write_file(dir.path() / name, "x");
  }
  const std::vector<int> frames = FramePattern(dir.file("m.####.ply")).discover();
  EXPECT_EQ(frames, (std::vector<int>{1, 2, 10, 12345}));
  EXPECT_EQ(FramePattern(dir.file("m.%04d.ply")).discover(), frames);
  EXPECT_EQ(FramePattern(dir.file("m.$F4.ply")).discover(), frames);
  EXPECT_TRUE(FramePattern(dir.file("nothing.####.ply")).discover().empty());
  EXPECT_TRUE(FramePattern(dir.file("sub/m.####.ply")).discover().empty());
}

TEST(FramePattern, DiscoversUnpadded) {
  test::TempDir dir;
  for (const char* name : {"m.1.ply", "m.2.ply", "m.10.ply", "m.07.ply"}) test::write_file(dir.path() / name, "x");
  EXPECT_EQ(FramePattern(dir.file("m.$F.ply")).discover(), (std::vector<int>{1, 2, 10}));
}

TEST(FramePattern, AUdimTokenNamesEveryTileOfAFrame) {
  const FramePattern p("out/atlas.####.<UDIM>.exr");
  EXPECT_TRUE(p.has_udim());
  EXPECT_FALSE(FramePattern("out/atlas.####.exr").has_udim());
  EXPECT_EQ(p.path(7), "out/atlas.0007.<UDIM>.exr");  // the name a material gives
  EXPECT_EQ(p.path(7, 1002), "out/atlas.0007.1002.exr");
  EXPECT_EQ(p.first_file(7), "out/atlas.0007.1001.exr");
  EXPECT_EQ(FramePattern("t.<UDIM>.$F4.exr").path(3, 1011), "t.1011.0003.exr");
  EXPECT_EQ(FramePattern("a.####.exr").path(3, 1002), "a.0003.exr");  // no token: one file
  EXPECT_THROW(FramePattern("a.<UDIM>.####.<UDIM>.exr"), InputError);
  EXPECT_THROW(FramePattern("tiles_<UDIM>/a.####.exr"), InputError);

  test::TempDir dir;
  for (const char* name : {"a.0001.1001.exr", "a.0001.1002.exr", "a.0001.1011.exr", "a.0002.1001.exr",
                           "a.0003.1002.exr", "a.0001.0999.exr", "a.0001.101.exr", "a.0001.1003.exr.tmp"}) {
    test::write_file(dir.path() / name, "x");
  }
  const FramePattern tiles(dir.file("a.####.<UDIM>.exr"));
  EXPECT_EQ(tiles.udims(1), (std::vector<int>{1001, 1002, 1011}));
  EXPECT_EQ(tiles.files(1), (std::vector<std::string>{dir.file("a.0001.1001.exr"), dir.file("a.0001.1002.exr"),
                                                      dir.file("a.0001.1011.exr")}));
  EXPECT_TRUE(tiles.udims(4).empty());
  // A frame is on disk when its tile 1001 is (frame 3 has only 1002).
  EXPECT_EQ(tiles.discover(), (std::vector<int>{1, 2}));
}

TEST(FrameRange, Ranges) {
  EXPECT_EQ(parse_frame_range("1-5"), (std::vector<int>{1, 2, 3, 4, 5}));
  EXPECT_EQ(parse_frame_range("1-10x3"), (std::vector<int>{1, 4, 7, 10}));
  EXPECT_EQ(parse_frame_range("7"), (std::vector<int>{7}));
  EXPECT_EQ(parse_frame_range("1-3,10-14x2,2"), (std::vector<int>{1, 2, 3, 10, 12, 14}));
  EXPECT_EQ(parse_frame_range("-2-1"), (std::vector<int>{-2, -1, 0, 1}));
}

TEST(FrameRange, FormatsWhatItParses) {
  EXPECT_EQ(format_frame_range({}), "");
  EXPECT_EQ(format_frame_range({7}), "7");
  EXPECT_EQ(format_frame_range({1, 2, 3, 4}), "1-4");
  EXPECT_EQ(format_frame_range({1, 3, 5, 7}), "1-7x2");
  EXPECT_EQ(format_frame_range({1, 3}), "1,3");
  EXPECT_EQ(format_frame_range({-2, -1, 0}), "-2-0");
  for (const char* text : {"1-48", "1-3,10-14x2", "5,9,20-30x5", "-4-4x4,100", "1,2,4,8,16"}) {
    const std::vector<int> frames = parse_frame_range(text);
    EXPECT_EQ(parse_frame_range(format_frame_range(frames)), frames) << text;
  }
}

TEST(FrameRange, RejectsMalformed) {
  for (const char* bad : {"", "a-b", "5-1", "1-10x0", "1-10x-2", "1-", "1,,2", "1-10y2", "3.5"}) {
    EXPECT_THROW(parse_frame_range(bad), InputError) << bad;
  }
}

TEST(Sequence, MissingFrameInRangeIsNamed) {
  test::TempDir dir;
  for (const char* name : {"m.0001.ply", "m.0002.ply", "m.0004.ply"}) test::write_file(dir.path() / name, "x");
  InputOptions in;
  in.pattern = dir.file("m.####.ply");
  EXPECT_EQ(Sequence(in).frames(), (std::vector<int>{1, 2, 4}));
  in.frames = "1-4";
  try {
    Sequence s(in);
    FAIL() << "a missing frame must be an error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), dir.file("m.0003.ply"));
    EXPECT_NE(e.problem().find("missing"), std::string::npos);
  }
  in.frames = "1-4x3";
  EXPECT_EQ(Sequence(in).frames(), (std::vector<int>{1, 4}));
}

TEST(Sequence, NoFramesIsAnError) {
  test::TempDir dir;
  InputOptions in;
  in.pattern = dir.file("m.####.ply");
  EXPECT_THROW(Sequence s(in), InputError);
}

/// An n×n grid in the plane z = 0 as OBJ, moved by `shift` and stretched
/// along x by `stretch`, its vertices numbered through `order` (vertex k of
/// the grid is written at position order[k]).
std::string grid_obj(int n, const Vec3& shift, double stretch, const std::vector<int>& order) {
  std::vector<Vec3> at(static_cast<std::size_t>(n * n));
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) at[order[y * n + x]] = Vec3(x * stretch, y, 0) + shift;
  }
  std::string text;
  for (const Vec3& p : at) text += "v " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " 0\n";
  for (int y = 0; y + 1 < n; ++y) {
    for (int x = 0; x + 1 < n; ++x) {
      const int a = order[y * n + x] + 1, b = order[y * n + x + 1] + 1, c = order[(y + 1) * n + x + 1] + 1,
                d = order[(y + 1) * n + x] + 1;
      text += "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c) + "\n";
      text += "f " + std::to_string(a) + " " + std::to_string(c) + " " + std::to_string(d) + "\n";
    }
  }
  return text;
}

TEST(Sequence, VelocityFromPositionsNeedsVerticesThatCorrespond) {
  test::TempDir dir;
  const int n = 8;
  std::vector<int> order(n * n);
  for (int k = 0; k < n * n; ++k) order[k] = k;
  std::vector<int> renumbered = order;
  std::reverse(renumbered.begin(), renumbered.end());  // the same surface, numbered anew
  InputOptions in;
  in.pattern = dir.file("g.####.obj");
  in.velocity_from_positions = true;
  in.fps = 10;
  // Moving by 3 cells and stretching by 30% per frame: fast, but one mesh.
  for (int f = 1; f <= 3; ++f)
    test::write_file(dir.path() / FramePattern("g.####.obj").path(f),
                     grid_obj(n, Vec3(3.0 * f, 0, 0), 1.0 + 0.3 * f, order));
  const FrameMesh m = Sequence(in).load(1);
  EXPECT_NEAR(m.velocities[0].x(), 30.0, 1e-3);  // (9 − 3) / 0.2 s for the corner at x = 0
  // The middle frame renumbered: same vertex count, same surface; refused, naming it.
  test::write_file(dir.path() / "g.0002.obj", grid_obj(n, Vec3(6, 0, 0), 1.6, renumbered));
  try {
    (void)Sequence(in).load(0);
    FAIL() << "a renumbered frame must be refused";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), dir.file("g.0002.obj"));
    EXPECT_NE(e.problem().find("do not correspond"), std::string::npos) << e.what();
  }
}

TEST(Sequence, AStepRangeFollowsTheFramesOnDiskBetweenItsFrames) {
  test::TempDir dir;
  std::vector<int> order(16);
  for (int k = 0; k < 16; ++k) order[k] = k;
  for (int f = 1; f <= 8; ++f) {
    if (f == 5) continue;  // not on disk
    test::write_file(dir.path() / FramePattern("g.####.obj").path(f), grid_obj(4, Vec3(f, 0, 0), 1.0, order));
  }
  std::filesystem::remove(dir.path() / "g.0002.obj");
  std::filesystem::create_directory(dir.path() / "g.0002.obj");  // a folder named like a frame: not one
  InputOptions in;
  in.pattern = dir.file("g.####.obj");
  in.velocity_from_positions = true;
  in.frames = "1-7x3";
  EXPECT_EQ(Sequence(in).frames(), (std::vector<int>{1, 4, 7}));
  EXPECT_EQ(Sequence(in).followed_frames(), (std::vector<int>{1, 3, 4, 6, 7}));  // 8 is after the end
  in.skipped_frames = SkippedFrames::Ignore;
  EXPECT_EQ(Sequence(in).followed_frames(), (std::vector<int>{1, 4, 7}));
  in.skipped_frames = SkippedFrames::Follow;
  in.frames = "6-8";  // consecutive frames on disk: nothing between them
  EXPECT_EQ(Sequence(in).followed_frames(), Sequence(in).frames());
}

TEST(Sequence, TheFollowedSequenceDerivesVelocitiesOverTheFramesBetween) {
  // A grid moving along x by f²/2 and stretching by f³: at frame 4 the
  // central differences over frames 3 and 5 (what a run following 1-7x3
  // reads) differ from those over 1 and 7 (the stepped range alone).
  test::TempDir dir;
  std::vector<int> order(16);
  for (int k = 0; k < 16; ++k) order[k] = k;
  for (int f = 1; f <= 7; ++f) {
    test::write_file(dir.path() / FramePattern("g.####.obj").path(f),
                     grid_obj(4, Vec3(0.5 * f * f, 0, 0), 1.0 + 0.002 * f * f * f, order));
  }
  InputOptions in;
  in.pattern = dir.file("g.####.obj");
  in.velocity_from_positions = true;
  in.fps = 1;
  in.frames = "1-7";
  const FrameMesh every = Sequence(in).load(3);  // frame 4
  in.frames = "1-7x3";
  const Sequence stepped(in);
  const Sequence followed = stepped.followed();
  ASSERT_EQ(followed.frames(), (std::vector<int>{1, 2, 3, 4, 5, 6, 7}));
  const FrameMesh through = followed.load(3);
  const FrameMesh across = stepped.load(1);
  ASSERT_EQ(through.velocities.size(), every.velocities.size());
  for (std::size_t v = 0; v < every.velocities.size(); ++v) EXPECT_EQ(through.velocities[v], every.velocities[v]) << v;
  EXPECT_NE(across.velocities.back(), every.velocities.back());  // the stepped range alone: other neighbours
  in.skipped_frames = SkippedFrames::Ignore;
  EXPECT_EQ(Sequence(in).followed().frames(), stepped.frames());
}

TEST(Sequence, TheFrameRateIsTheOneTheFirstFrameStatesUnlessGiven) {
  test::TempDir dir;
  const FrameMesh mesh = test::flat_grid(1, 1.0, 0.0, 0.0, 0.0, [](const Vec3&) { return Vec3(1, 0, 0); });
  for (int f = 1; f <= 3; ++f) write_frame_ply(dir.file(FramePattern("s.####.ply").path(f)), mesh, 30.0);
  for (int f = 1; f <= 2; ++f) write_frame_ply(dir.file(FramePattern("n.####.ply").path(f)), mesh);
  InputOptions in;
  in.pattern = dir.file("s.####.ply");
  const Sequence stated(in);
  EXPECT_EQ(stated.stated_fps(), 30.0);
  EXPECT_EQ(stated.fps(), 30.0);
  EXPECT_EQ(stated.fps_source(), FpsSource::Header);
  in.frames = "1-3x2";
  EXPECT_EQ(Sequence(in).followed().fps(), 30.0);
  EXPECT_EQ(Sequence(in).followed().fps_source(), FpsSource::Header);
  in.fps = 24.0;  // given: it wins
  EXPECT_EQ(Sequence(in).fps(), 24.0);
  EXPECT_EQ(Sequence(in).stated_fps(), 30.0);
  EXPECT_EQ(Sequence(in).fps_source(), FpsSource::Given);
  in = InputOptions{};
  in.pattern = dir.file("n.####.ply");
  EXPECT_EQ(Sequence(in).stated_fps(), std::nullopt);
  EXPECT_EQ(Sequence(in).fps(), Sequence::kDefaultFps);
  EXPECT_EQ(Sequence(in).fps_source(), FpsSource::Default);
}

TEST(Options, DefaultsAndValidation) {
  TrackingOptions o;
  EXPECT_NO_THROW(o.validate());
  const TrackingOptions r = o.resolved(2.0);
  EXPECT_DOUBLE_EQ(r.d(), 0.1);
  EXPECT_DOUBLE_EQ(r.mpt(), 0.025);
  EXPECT_DOUBLE_EQ(r.cs(), 0.025);
  EXPECT_THROW(o.d(), InternalError);  // not resolved
  o.radius = 0.3;
  EXPECT_DOUBLE_EQ(o.resolved(2.0).d(), 0.3);
  o.radius = 0.0;
  EXPECT_THROW(o.validate(), InputError);  // a length is > 0 or left automatic
  o.radius.reset();
  o.max_distortion = 1.0;
  EXPECT_THROW(o.validate(), InputError);
  o = TrackingOptions{};
  o.fade_frames = 0;
  EXPECT_THROW(o.validate(), InputError);
  o = TrackingOptions{};
  o.plane_angle = std::nan("");
  EXPECT_THROW(o.validate(), InputError);
  EXPECT_EQ(parse_enum<Criterion>("sphere", "criterion"), Criterion::Sphere);
  EXPECT_EQ(parse_enum<Fading>("linear", "fading"), Fading::Linear);
  EXPECT_THROW(parse_enum<Criterion>("cube", "criterion"), InputError);
}

TEST(Options, EveryTable3And4ParameterIsVisited) {
  TrackingOptions o;
  std::vector<std::string> names;
  TrackingOptions::for_each_option(o, [&](const OptionInfo& info, auto&) { names.emplace_back(info.name); });
  for (const char* expected : {"radius", "plane-angle", "patch-vertex-angle", "max-distortion", "uv-scale",
                               "max-projection", "fade-frames", "thickness", "kill-alpha", "min-vertex-quality"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
  }
}

}  // namespace
}  // namespace fluidtex
