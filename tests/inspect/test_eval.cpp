// `fluidtex eval`: every metric on a case with a known answer, and the whole
// command on a generated scene.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>

#include "fluidtex/geometry/surface.h"
#include "fluidtex/inspect/eval.h"
#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/scenes/exemplar_gen.h"
#include "fluidtex/tracking/patch_coverage.h"
#include "fluidtex/util/error.h"
#include "mesh_fixtures.h"
#include "synthesis_fixtures.h"
#include "test_util.h"

namespace fluidtex {
namespace {

/// A flat n×n grid over [x0, x0+1]×[0,1] whose uvs are fixed to its
/// vertices (uv = vertex position at x0 = 0): moving x0 moves the texture
/// with the surface.
UVMesh moving_grid(int n, double x0) {
  const FrameMesh grid = test::flat_grid(n, 1.0, 0.0, x0, 0.0);
  UVMesh m;
  m.positions = grid.positions;
  m.normals.assign(grid.positions.size(), Vec3::UnitZ());
  m.triangles = grid.triangles;
  for (const Vec3& p : grid.positions) m.uvs.emplace_back(p.x() - x0, p.y());
  m.uv_triangles = grid.triangles;
  return m;
}

TEST(Eval, CoverageIsOneWithoutPatches) {
  const FrameMesh grid = test::flat_grid(6);
  const SurfaceIndex surface(grid);
  const std::vector<Patch> none;
  EXPECT_DOUBLE_EQ(uncovered_area_fraction(surface, PatchCoverage(none, 0.01), 0.05), 1.0);
}

TEST(Eval, WarpingErrorIsZeroForAnAdvectedTextureAndLargeForARandomOne) {
  const Exemplar exemplar(make_exemplar("gravel", 128, 4));
  const double dt = 1.0 / 24.0, speed = 0.12;  // the surface moves 5 mm per frame along x
  FrameMesh mesh = test::flat_grid(10, 1.0, 0.0, 0.0, 0.0);
  mesh.velocities.assign(mesh.positions.size(), Vec3(speed, 0.0, 0.0));
  const TexturedFrame t0(moving_grid(10, 0.0), exemplar.image());
  std::optional<TexturedFrame> moved;  // frames are moved around by eval: the index must follow
  moved.emplace(TexturedFrame(moving_grid(10, speed * dt), exemplar.image()));
  const TexturedFrame t1(std::move(*moved));
  moved.reset();
  const WarpingError w = warping_error(mesh, t0, t1, LiquidMotion(dt), exemplar, 4000, 7);
  EXPECT_EQ(w.samples, 4000u);
  EXPECT_LT(w.advected, 1e-3);  // exactly advected, no distortion
  EXPECT_GT(w.fixed, 0.1);      // the texture moved under a fixed point
  EXPECT_GT(w.random, 0.5);     // uncorrelated colours: about 2/sqrt(pi) σ for Gaussian noise
  // A texture unrelated to the last frame's: as bad as random.
  const TexturedFrame other(moving_grid(10, speed * dt), make_exemplar("gravel", 128, 99));
  const WarpingError r = warping_error(mesh, t0, other, LiquidMotion(dt), exemplar, 4000, 7);
  EXPECT_GT(r.advected, 0.5 * w.random);
}

TEST(Eval, TheLiquidIsCarriedThroughTheFramesBetweenTwoMeasured) {
  // Frame t moves along x; the frame after it, which a stepped run skips,
  // moves along y: two frames later a point has gone both ways.
  const double dt = 1.0 / 24.0;
  FrameMesh between = test::flat_grid(10, 1.0, 0.0, 0.0, 0.0);
  between.velocities.assign(between.positions.size(), Vec3(0.0, 0.6, 0.0));
  LiquidMotion motion(dt);
  EXPECT_TRUE(motion.carry(Vec3(0.5, 0.5, 0.0), Vec3(0.3, 0.0, 0.0)).isApprox(Vec3(0.5 + 0.3 * dt, 0.5, 0.0)));
  motion.add_step(std::make_shared<const FrameMesh>(between), 2 * dt);
  EXPECT_TRUE(
      motion.carry(Vec3(0.5, 0.5, 0.0), Vec3(0.3, 0.0, 0.0)).isApprox(Vec3(0.5 + 0.3 * dt, 0.5 + 1.2 * dt, 0.0), 1e-9));

  // A texture that went along x and then along y is where the motion says.
  const Exemplar exemplar(make_exemplar("gravel", 128, 4));
  FrameMesh mesh = test::flat_grid(10, 1.0, 0.0, 0.0, 0.0);
  mesh.velocities.assign(mesh.positions.size(), Vec3(0.3, 0.0, 0.0));
  const TexturedFrame t0(moving_grid(10, 0.0), exemplar.image());
  UVMesh moved = moving_grid(10, 0.3 * dt);
  for (Vec3& p : moved.positions) p.y() += 1.2 * dt;  // uvs stay: the texture moves with it
  const TexturedFrame t2(std::move(moved), exemplar.image());
  EXPECT_LT(warping_error(mesh, t0, t2, motion, exemplar, 4000, 7).advected, 1e-3);
  EXPECT_GT(warping_error(mesh, t0, t2, LiquidMotion(3 * dt), exemplar, 4000, 7).advected, 0.1);
}

TEST(Eval, OpticalFlowFindsATranslation) {
  const Image texture = make_exemplar("gravel", 128, 5);
  const int n = 96, dx = 2, dy = 1;
  Image a, b, expected;
  a.width = b.width = expected.width = a.height = b.height = expected.height = n;
  a.channels = b.channels = 3;
  expected.channels = 2;
  a.pixels.resize(n * n * 3), b.pixels.resize(n * n * 3), expected.pixels.resize(n * n * 2);
  std::vector<char> mask(n * n, 0);
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      for (int c = 0; c < 3; ++c) {
        a.pixels[(y * n + x) * 3 + c] = texture.at(x + 8, y + 8, c);
        b.pixels[(y * n + x) * 3 + c] = texture.at(x + 8 - dx, y + 8 - dy, c);  // content moved by (dx, dy)
      }
      expected.pixels[(y * n + x) * 2] = dx, expected.pixels[(y * n + x) * 2 + 1] = dy;
      mask[y * n + x] = x >= 16 && y >= 16 && x < n - 16 && y < n - 16;
    }
  }
  const FlowError e = optical_flow_error(a, b, expected, mask);
  EXPECT_GT(e.pixels, 3000u);
  EXPECT_LT(e.endpoint, 0.3);
  EXPECT_LT(e.angular, 5.0);
  EXPECT_NEAR(e.speed, std::hypot(dx, dy), 1e-9);
  // Against a wrong expectation the error is about the difference.
  for (std::size_t i = 0; i < expected.pixels.size(); i += 2) expected.pixels[i] = -dx;
  EXPECT_GT(optical_flow_error(a, b, expected, mask).endpoint, 3.0);
  // Pixels expected to move by the limit or more count in the overall means
  // only: here the left half, expected at 20 px.
  std::size_t slow = 0;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      expected.pixels[(y * n + x) * 2] = x < n / 2 ? 20.0f : dx;
      slow += mask[y * n + x] && x >= n / 2;
    }
  }
  const FlowError fast = optical_flow_error(a, b, expected, mask, 15.0);
  EXPECT_EQ(fast.pixels, e.pixels);
  EXPECT_EQ(fast.slow_pixels, slow);
  EXPECT_GT(fast.endpoint, 5.0);
  EXPECT_LT(fast.slow_endpoint, 0.3);
  EXPECT_NEAR(fast.slow_speed, std::hypot(dx, dy), 1e-9);
  EXPECT_EQ(optical_flow_error(a, b, expected, mask, 25.0).slow_pixels, e.pixels);
}

TEST(Eval, ContrastRatioIsOneForASinglePatch) {
  // One patch of weight 1 over the unit square showing exactly 4×4 tiles.
  // A smooth exemplar, so that bilinear lookups between its texels do not
  // lower the contrast themselves.
  Image smooth;
  smooth.width = smooth.height = 64;
  smooth.channels = 3;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      smooth.pixels.push_back(static_cast<float>(0.5 + 0.3 * std::sin(2 * M_PI * x / 64.0)));
      smooth.pixels.push_back(static_cast<float>(0.5 + 0.2 * std::cos(2 * M_PI * y / 32.0)));
      smooth.pixels.push_back(static_cast<float>(0.5 + 0.25 * std::sin(2 * M_PI * (x + y) / 64.0)));
    }
  }
  test::OnePatch scene(256);
  scene.add(Vec2(0.1, 0.3), 1.0);
  const Exemplar exemplar(smooth);
  SynthesisOptions so;
  so.tile_size = 0.25;
  so.radius = 1e3;
  const SynthesisResult r = synthesize(scene.surface, scene.atlas, scene.map, scene.patches, exemplar, so);
  std::vector<char> mask(scene.map.face.size());
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = scene.map.face[i] >= 0;
  for (double ratio : contrast_ratio(r.color, mask, exemplar)) EXPECT_NEAR(ratio, 1.0, 0.03);
  // Linear blending of four uncorrelated patches loses contrast.
  test::OnePatch four(256);
  for (int k = 0; k < 4; ++k) four.add(Vec2(0.13 * k + 0.05, 0.29 * k + 0.1), 1.0, 0.9 * k);
  so.blend = Blend::Linear;
  const SynthesisResult lin = synthesize(four.surface, four.atlas, four.map, four.patches, exemplar, so);
  for (double ratio : contrast_ratio(lin.color, mask, exemplar)) EXPECT_LT(ratio, 0.75);
}

TEST(Eval, SpectrumDistanceIsZeroForTheExemplarItself) {
  const Exemplar exemplar(make_exemplar("gravel", 128, 8));
  const std::vector<double> s = radial_log_spectrum(exemplar.image(), 0, 0, 64);
  ASSERT_EQ(s.size(), 31u);
  EXPECT_DOUBLE_EQ(spectrum_distance(s, s), 0.0);
  // The same texture resampled at scale 1 is the same spectrum; a blurred
  // one (half resolution) is not.
  const Image same = exemplar_crop(exemplar, 0.0, 0.0, 1.0, 64);
  EXPECT_LT(spectrum_distance(radial_log_spectrum(same, 0, 0, 64), s), 1e-6);
  const Image zoomed = exemplar_crop(exemplar, 0.0, 0.0, 0.5, 64);
  EXPECT_GT(spectrum_distance(radial_log_spectrum(zoomed, 0, 0, 64), s), 0.5);
  EXPECT_THROW(radial_log_spectrum(exemplar.image(), 100, 0, 64), InternalError);
}

TEST(Eval, ChartMaskCoversTheUvTriangles) {
  const UVMesh m = moving_grid(4, 0.0);  // the whole [0,1]² in uv
  const std::vector<char> mask = chart_mask(m, 32);
  EXPECT_EQ(std::count(mask.begin(), mask.end(), 1), 32 * 32);
  UVMesh half = m;
  for (Vec2& uv : half.uvs) uv *= 0.5;  // lower-left quarter in uv = bottom-left in the image (y down)
  const std::vector<char> q = chart_mask(half, 32);
  EXPECT_EQ(std::count(q.begin(), q.end(), 1), 16 * 16);
  EXPECT_TRUE(q[31 * 32 + 0]);
  EXPECT_FALSE(q[0]);
}

TEST(Eval, CommandWritesMetricsAndReportOnAGeneratedScene) {
  test::TempDir dir;
  const std::string scene = dir.file("scene");
  ASSERT_EQ(test::run_fluidtex("gen rotation -o " + scene +
                               " --frames 5 --resolution 24 --exemplar gravel --exemplar-size 64"),
            0);
  const std::string out = dir.file("out");
  const std::string input = scene + "/rotation.####.ply";
  ASSERT_EQ(test::run_fluidtex("run -i '" + input + "' -e " + scene + "/gravel.png -o " + out + " --atlas-size 256 -q"),
            0);
  ASSERT_EQ(test::run_fluidtex("eval -i '" + input + "' -o " + out + " --samples 2000 -q"), 0);
  for (const char* f : {"metrics.jsonl", "summary.json", "report.html"}) {
    EXPECT_TRUE(std::filesystem::exists(out + "/eval/" + f)) << f;
  }
  const std::string summary = test::read_file(out + "/eval/summary.json");
  auto value = [&](const std::string& key) {
    const std::size_t at = summary.find("\"" + key + "\":");
    EXPECT_NE(at, std::string::npos) << key;
    return at == std::string::npos ? std::nan("") : std::stod(summary.substr(at + key.size() + 3));
  };
  EXPECT_EQ(value("frames"), 5);
  EXPECT_EQ(value("uncovered_area_mean"), 0.0);
  EXPECT_LT(value("warp_advected"), 0.5 * value("warp_fixed"));
  EXPECT_LT(value("warp_advected"), 0.5 * value("warp_random"));
  EXPECT_GT(value("ghosting_mean"), 1.0);
  EXPECT_LT(value("flow_endpoint_px"), 0.5 * value("flow_speed_px"));
  EXPECT_NEAR(value("contrast_g"), 1.0, 0.2);
  // The rigid rotation recuts nothing; the count is there, per frame.
  const std::string metrics = test::read_file(out + "/eval/metrics.jsonl");
  EXPECT_NE(metrics.find("\"recuts\":0"), std::string::npos);
  const std::string html = test::read_file(out + "/eval/report.html");
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_NE(html.find("data:image/png;base64,"), std::string::npos);
  // Not a run's folder: a clear error.
  EXPECT_EQ(test::run_fluidtex("eval -i '" + input + "' -o " + scene + " -q"), 2);
}

TEST(Eval, CheckPassesARunAndFailsAStillTexture) {
  // A run of the rotating scene, and the same run with every frame's atlas
  // and UV mesh replaced by frame 1's: a texture that stands still while the
  // liquid turns.
  test::TempDir dir;
  const std::string scene = dir.file("scene");
  ASSERT_EQ(test::run_fluidtex("gen rotation -o " + scene +
                               " --frames 5 --resolution 24 --exemplar gravel --exemplar-size 64"),
            0);
  const std::string good = dir.file("good"), still = dir.file("still");
  ASSERT_EQ(test::run_fluidtex("run -q -i '" + scene + "/rotation.####.ply' -e " + scene + "/gravel.png -o " + good +
                               " --atlas-size 256"),
            0);
  std::filesystem::copy(good, still, std::filesystem::copy_options::recursive);
  for (int f = 2; f <= 5; ++f) {
    for (const char* p : {"atlas.####.exr", "mesh.####.obj"})
      std::filesystem::copy_file(still + "/" + FramePattern(p).path(1), still + "/" + FramePattern(p).path(f),
                                 std::filesystem::copy_options::overwrite_existing);
  }
  const std::string eval = " --samples 2000 --flow-width 0 --check";
  std::string out;
  EXPECT_EQ(test::run_fluidtex("eval -o " + good + eval, &out), 0) << out;
  EXPECT_NE(out.find("verdict: "), std::string::npos) << out;
  EXPECT_EQ(test::read_file(good + "/eval/verdict.json").find("\"grade\":\"bad\""), std::string::npos);
  EXPECT_EQ(test::run_fluidtex("eval -o " + still + eval, &out), 1) << out;
  EXPECT_NE(out.find("verdict: bad: warping ratio"), std::string::npos) << out;
  EXPECT_NE(out.find("frames 2–5: the texture slides against the liquid"), std::string::npos) << out;
  const std::string verdict = test::read_file(still + "/eval/verdict.json");
  EXPECT_NE(verdict.find("\"grade\":\"bad\""), std::string::npos) << verdict;
  EXPECT_TRUE(std::filesystem::exists(still + "/eval/worst.0002.png") ||
              std::filesystem::exists(still + "/eval/worst.0003.png") ||
              std::filesystem::exists(still + "/eval/worst.0004.png") ||
              std::filesystem::exists(still + "/eval/worst.0005.png"));
  const std::string html = test::read_file(still + "/eval/report.html");
  EXPECT_NE(html.find("Verdict: <span"), std::string::npos);
  EXPECT_NE(html.find("href='#worst0'"), std::string::npos);
  // Without --check the verdict is reported, not enforced.
  EXPECT_EQ(test::run_fluidtex("eval -q -o " + still + " --samples 2000 --flow-width 0", &out), 0) << out;
  // Thresholds from the command line and from a file (the good run blends
  // about 1.9 patches per texel); a good bound above its bad one is refused.
  EXPECT_EQ(test::run_fluidtex("eval -q -o " + good + eval + " --ghosting-good 1 --ghosting-bad 1.5", &out), 1) << out;
  EXPECT_NE(out.find("verdict: bad: ghosting"), std::string::npos) << out;
  test::write_file(dir.path() / "t.toml", "[eval]\nghosting-good = 1\nghosting-bad = 1.5\n");
  EXPECT_EQ(test::run_fluidtex("eval -q -o " + good + eval + " --thresholds " + dir.file("t.toml"), &out), 1) << out;
  EXPECT_EQ(test::run_fluidtex(
                "eval -q -o " + good + eval + " --thresholds " + dir.file("t.toml") + " --ghosting-bad 3", &out),
            0)
      << out;
  EXPECT_EQ(test::run_fluidtex("eval -q -o " + still + eval + " --warping-good 0.9 --warping-bad 0.5", &out), 2) << out;
  EXPECT_NE(out.find("--warping-good 0.9 is above --warping-bad 0.5"), std::string::npos) << out;
  EXPECT_EQ(test::run_fluidtex("eval -q -o " + still + eval + " --thresholds " + dir.str(), &out), 2) << out;
}

TEST(Eval, AStepRunIsMeasuredThroughTheFramesItSkipsAndPerFrame) {
  // Every second frame of the merge scene (it makes patches every frame):
  // births per frame are the pair's births over two frames, and the texture
  // changes less along the liquid's motion through the frame between than
  // in place.
  test::TempDir dir;
  const std::string scene = dir.file("scene");
  ASSERT_EQ(
      test::run_fluidtex("gen merge -o " + scene + " --frames 5 --resolution 20 --exemplar gravel --exemplar-size 32"),
      0);
  const std::string out = dir.file("out"), input = scene + "/merge.####.ply";
  ASSERT_EQ(test::run_fluidtex("run -i '" + input + "' -e " + scene + "/gravel.png -o " + out +
                               " --atlas-size 128 --frames 1-5x2 -q"),
            0);
  ASSERT_EQ(test::run_fluidtex("eval -i '" + input + "' -o " + out + " --samples 2000 --flow-width 0 -q"), 0);
  std::istringstream lines(test::read_file(out + "/eval/metrics.jsonl"));
  auto number = [](const std::string& line, const std::string& key) {
    const std::size_t at = line.find("\"" + key + "\":");
    EXPECT_NE(at, std::string::npos) << key;
    return at == std::string::npos ? std::nan("") : std::stod(line.substr(at + key.size() + 3));
  };
  int pairs = 0;
  double births = 0;
  for (std::string line; std::getline(lines, line);) {
    if (number(line, "frame") == 1) continue;
    ++pairs;
    births += number(line, "births");
    EXPECT_NEAR(number(line, "birth_rate"), number(line, "births") / number(line, "patches") / 2, 1e-12);
    EXPECT_LT(number(line, "warp_advected"), number(line, "warp_fixed")) << line;  // moves with the liquid
    // Where the births are, by the surface change: every birth in one class.
    double by_class = 0;
    for (const char* c : {"sink_fast", "sink", "kept", "source", "source_fast"})
      by_class += number(line, std::string("births_") + c);
    EXPECT_EQ(by_class, number(line, "births")) << line;
  }
  EXPECT_EQ(pairs, 2);
  EXPECT_GT(births, 0);
}

}  // namespace
}  // namespace fluidtex
