// `fluidtex eval` as a command: its outputs on a generated scene, --check's
// gate, and a stepped run. The figures it computes are tested on cases with
// known answers in test_texture_metrics and test_motion_metrics.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>

#include "fluidtex/io/frame_pattern.h"
#include "test_util.h"

namespace fluidtex {
namespace {

TEST(Eval, CommandWritesMetricsAndReportOnAGeneratedScene) {
  test::TempDir dir;
  const std::string scene = dir.file("scene");
  ASSERT_EQ(test::run_fluidtex("gen rotation -o " + scene +
                               " --frames 5 --resolution 24 --exemplar gravel --exemplar-pixels 64"),
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
  // As the exemplar looks: as directional, windows as close to it as its
  // own, the same colours.
  EXPECT_NEAR(value("orientation_coherence_ratio"), 1.0, 0.2);
  EXPECT_LT(value("window_energy_ratio"), 1.5);
  EXPECT_LT(value("histogram_distance"), 0.1);
  // The rigid rotation recuts nothing; the count is there, per frame.
  const std::string metrics = test::read_file(out + "/eval/metrics.jsonl");
  EXPECT_NE(metrics.find("\"recuts\":0"), std::string::npos);
  const std::string html = test::read_file(out + "/eval/report.html");
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_NE(html.find("data:image/png;base64,"), std::string::npos);
  EXPECT_NE(html.find("Texture against the exemplar"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(out + "/eval/exemplar_at_scale.png"));
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
                               " --frames 5 --resolution 24 --exemplar gravel --exemplar-pixels 64"),
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
  ASSERT_EQ(test::run_fluidtex("gen merge -o " + scene +
                               " --frames 5 --resolution 20 --exemplar gravel --exemplar-pixels 32"),
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
