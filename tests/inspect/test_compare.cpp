// fluidtex compare: two runs compared on the surface. Identical runs and a
// different atlas layout of the same texture pass; another exemplar differs;
// bad folders are exit 2 with one line.
#include <gtest/gtest.h>

#include "fluidtex/inspect/compare.h"
#include "fluidtex/inspect/texture_metrics.h"
#include "fluidtex/io/image_io.h"
#include "fluidtex/io/uv_mesh_io.h"
#include "fluidtex/scenes/exemplar_gen.h"
#include "fluidtex/util/error.h"
#include "test_util.h"

namespace fluidtex {
namespace {

class Compare : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir();
    test::write_rotation_scene(dir_->path(), 3, 16, "ex.png", 64);
    write_image(dir_->file("other.png"), make_exemplar("gravel", 64, 2));
    const std::string in = "-q -i " + dir_->file("rotation.####.ply") + " --atlas-size 512 ";
    ASSERT_EQ(test::run_fluidtex("run " + in + "-e " + dir_->file("ex.png") + " -o " + dir_->file("golden")), 0);
    ASSERT_EQ(test::run_fluidtex("run " + in + "-e " + dir_->file("ex.png") + " -o " + dir_->file("same")), 0);
    ASSERT_EQ(
        test::run_fluidtex("run " + in + "-e " + dir_->file("ex.png") + " --gutter 9 -o " + dir_->file("repacked")), 0);
    ASSERT_EQ(test::run_fluidtex("run " + in + "-e " + dir_->file("other.png") + " -o " + dir_->file("other")), 0);
    ASSERT_EQ(test::run_fluidtex("run " + in + "-e " + dir_->file("ex.png") + " -o " + dir_->file("ply") + " --mesh " +
                                 dir_->file("ply/mesh.####.ply")),
              0);
    ASSERT_EQ(
        test::run_fluidtex("run " + in + "-e " + dir_->file("ex.png") + " --frames 1-2 -o " + dir_->file("shorter")),
        0);
  }
  static void TearDownTestSuite() { delete dir_; }
  static Comparison compare(const std::string& candidate) {
    CompareOptions o;
    o.golden = dir_->file("golden");
    o.candidate = dir_->file(candidate);
    o.samples = 20000;
    return compare_runs(o, silent_reporter());
  }
  static test::TempDir* dir_;
};
test::TempDir* Compare::dir_ = nullptr;

TEST_F(Compare, SameTextureWhateverTheLayoutAnotherExemplarDiffers) {
  const Comparison same = compare("same");
  ASSERT_EQ(same.frames.size(), 3u);
  EXPECT_TRUE(same.passed);
  for (const FrameComparison& f : same.frames) {
    EXPECT_EQ(f.samples, 20000u);
    EXPECT_EQ(f.max, 0.0);
  }
  // A wider gutter packs the charts elsewhere: the atlases differ texel for
  // texel, the textured surface does not (beyond resampling).
  EXPECT_NE(test::read_file(dir_->file("golden/atlas.0002.exr")),
            test::read_file(dir_->file("repacked/atlas.0002.exr")));
  const Comparison c = compare("repacked");
  EXPECT_TRUE(c.passed) << format_comparison(c, CompareOptions{});
  for (const FrameComparison& f : c.frames) EXPECT_LT(f.mean, 0.005);  // measured 0.0033 (resampling)
  // Another exemplar is another texture.
  const Comparison d = compare("other");
  EXPECT_FALSE(d.passed);
  for (const FrameComparison& f : d.frames) {
    EXPECT_FALSE(f.passed);
    EXPECT_GT(f.mean, 0.05);  // measured 0.13
  }
  const std::string table = format_comparison(d, CompareOptions{});
  EXPECT_NE(table.find("DIFFERS"), std::string::npos);
  EXPECT_NE(table.find("differs: 3 of 3 frames"), std::string::npos) << table;
}

TEST_F(Compare, AFewDamagedTexelsFailTexelByTexelAndAreLocated) {
  // Twelve chart texels of frame 2 raised by 0.3: too few for the sampled
  // mean and percentile, not for the texel-by-texel check of two runs of one
  // layout, which names the worst texel and where it lies.
  const Comparison same = compare("same");
  for (const FrameComparison& f : same.frames) {
    EXPECT_GT(f.texels, 10000u);
    EXPECT_EQ(f.texel_max, 0.0);
  }
  test::TempDir copy;
  std::filesystem::copy(dir_->file("same"), copy.path() / "run", std::filesystem::copy_options::recursive);
  const std::string atlas = (copy.path() / "run" / "atlas.0002.exr").string();
  Image damaged = read_image(atlas);
  const std::vector<char> charts = chart_mask(read_uv_mesh(dir_->file("same/mesh.0002.obj")), damaged.width);
  int changed = 0;
  for (std::size_t i = charts.size() / 2; i < charts.size() && changed < 12; ++i) {
    if (!charts[i]) continue;
    damaged.pixel(i)[1] = std::min(1.0f, damaged.pixel(i)[1] + 0.3f);
    ++changed;
  }
  write_image(atlas, damaged);
  CompareOptions o;
  o.golden = dir_->file("golden");
  o.candidate = (copy.path() / "run").string();
  o.samples = 20000;
  const Comparison c = compare_runs(o, silent_reporter());
  ASSERT_EQ(c.frames.size(), 3u);
  EXPECT_FALSE(c.passed);
  EXPECT_TRUE(c.frames[0].passed);
  EXPECT_FALSE(c.frames[1].passed);
  EXPECT_LT(c.frames[1].mean, o.mean_tolerance);  // what the statistics alone would have passed
  EXPECT_LE(c.frames[1].percentile, o.percentile_tolerance);
  EXPECT_GT(c.frames[1].texel_max, 0.2);
  const std::string table = format_comparison(c, o);
  EXPECT_NE(table.find("frame 2: worst texel ("), std::string::npos) << table;
  EXPECT_NE(table.find("differs: 1 of 3 frames"), std::string::npos) << table;
  // Another layout (a wider gutter) is compared on the surface only.
  for (const FrameComparison& f : compare("repacked").frames) EXPECT_EQ(f.texels, 0u);
}

TEST_F(Compare, CommandExitsZeroOneOrTwo) {
  const std::string golden = dir_->file("golden");
  std::string out;
  EXPECT_EQ(test::run_fluidtex("compare -q " + golden + " " + dir_->file("repacked"), &out), 0) << out;
  EXPECT_EQ(out.rfind("same: 0 of 3 frames", 0), 0u) << out;
  EXPECT_EQ(test::run_fluidtex("compare " + golden + " " + dir_->file("other"), &out), 1) << out;
  EXPECT_NE(out.find("| 2 | 50000 |"), std::string::npos) << out;
  // Bad input: a folder that is no run, runs of other frames, a missing atlas.
  EXPECT_EQ(test::run_fluidtex("compare " + golden + " " + dir_->file("nowhere"), &out), 2);
  EXPECT_NE(out.find("nowhere"), std::string::npos) << out;
  EXPECT_EQ(test::run_fluidtex("compare " + golden + " " + dir_->file("shorter"), &out), 2);
  EXPECT_NE(out.find("covers frames 1-2, the golden run 1-3"), std::string::npos) << out;
  test::TempDir copy;
  std::filesystem::copy(dir_->file("same"), copy.path() / "run", std::filesystem::copy_options::recursive);
  std::filesystem::remove(copy.path() / "run" / "atlas.0003.exr");
  EXPECT_EQ(test::run_fluidtex("compare " + golden + " " + (copy.path() / "run").string(), &out), 2);
  EXPECT_NE(out.find("atlas.0003.exr"), std::string::npos) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  // An atlas with more channels than a colour lookup holds (5) is refused,
  // not read past its buffer.
  write_image((copy.path() / "run" / "atlas.0003.exr").string(), Image::blank(8, 8, 5));
  EXPECT_EQ(test::run_fluidtex("compare " + golden + " " + (copy.path() / "run").string(), &out), 2);
  EXPECT_NE(out.find("atlas.0003.exr: 5 channels"), std::string::npos) << out;
}

TEST_F(Compare, AndEvalAndPreviewReadPlyUvMeshesAsOnesOfObj) {
  // The run with PLY UV meshes is the golden run's texture.
  const Comparison same = compare("ply");
  ASSERT_EQ(same.frames.size(), 3u);
  for (const FrameComparison& f : same.frames) EXPECT_EQ(f.max, 0.0);
  std::string out;
  // preview finds the run's meshes through its job.toml, and renders what
  // the OBJ run's preview renders.
  for (const char* run : {"golden", "ply"})
    ASSERT_EQ(test::run_fluidtex("preview " + dir_->file(run) + " --frames 2 --width 64", &out), 0) << out;
  EXPECT_EQ(test::read_file(dir_->file("ply/preview/frame.0002.png")),
            test::read_file(dir_->file("golden/preview/frame.0002.png")));
  // eval reads the input job.toml records (no -i) and the PLY meshes.
  ASSERT_EQ(test::run_fluidtex("eval -q -o " + dir_->file("ply") + " --samples 2000 --flow-width 0", &out), 0) << out;
  ASSERT_EQ(test::run_fluidtex("eval -q -o " + dir_->file("golden") + " --samples 2000 --flow-width 0", &out), 0)
      << out;
  EXPECT_EQ(test::read_file(dir_->file("ply/eval/summary.json")),
            test::read_file(dir_->file("golden/eval/summary.json")));
}

}  // namespace
}  // namespace fluidtex
