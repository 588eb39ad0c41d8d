// The job's options table (job/job_options.h): one entry per option, the
// job.toml a run writes and eval reads back.
#include <gtest/gtest.h>

#include <set>

#include "fluidtex/io/sequence.h"
#include "fluidtex/job/job_options.h"
#include "fluidtex/job/job_record.h"
#include "fluidtex/job/pipeline.h"
#include "fluidtex/scenes/scenes.h"
#include "fluidtex/util/version.h"
#include "mesh_fixtures.h"
#include "test_util.h"

namespace fluidtex {
namespace {

TEST(JobOptions, EveryOptionIsListedOnceWithHelp) {
  JobOptions o;
  std::set<std::string> names;
  for (const OptionRef& ref : option_table(o)) {
    EXPECT_TRUE(names.insert(ref.info.name).second) << ref.info.name;
    EXPECT_GT(std::string(ref.info.help).size(), 10u) << ref.info.name;
  }
  for (const char* expected : {"input", "output", "exemplar", "radius", "fading", "method", "flowmap-period",
                               "atlas-size", "aov", "float", "no-coverage-check", "seed", "threads"}) {
    EXPECT_TRUE(names.count(expected)) << expected;
  }
}

TEST(JobOptions, JobTomlReadsBackUnchanged) {
  test::TempDir dir;
  JobOptions o;
  o.input.pattern = "in/mesh.####.ply";
  o.output.dir = "out";
  o.tracking.radius = 0.0625;
  o.tracking.fading = Fading::Linear;
  o.synthesis.aov = {"weight", "count"};
  o.synthesis.float_output = true;
  o.no_coverage_check = true;
  o.seed = 99;
  const std::string text = job_toml(o);
  test::write_file(dir.path() / "job.toml", text);
  const JobOptions back = read_job_manifest(dir.str());
  EXPECT_EQ(job_toml(back), text);
  EXPECT_EQ(back.tracking.radius, 0.0625);
  EXPECT_FALSE(back.tracking.thickness.has_value());
  EXPECT_THROW(read_job_manifest(dir.file("nowhere")), InputError);
}

TEST(JobOptions, ReadsTheJobTomlOfEarlierVersions) {
  // fluidtex 0.1 wrote console settings, and 0 for an automatic length.
  test::TempDir dir;
  test::write_file(dir.path() / "job.toml", "verbose=false\nquiet=true\nradius=0\nthickness=0.5\nseed=4\n");
  const JobOptions o = read_job_manifest(dir.str());
  EXPECT_FALSE(o.tracking.radius.has_value());
  EXPECT_EQ(o.tracking.thickness, 0.5);
  EXPECT_EQ(o.seed, 4u);
}

TEST(JobOptions, RunJobWritesItsJobToml) {
  test::TempDir dir;
  test::write_rotation_scene(dir.path(), 2, 8, "");
  JobOptions job;
  job.input.pattern = dir.file("rotation.####.ply");
  job.output.dir = dir.file("out");
  job.synthesis.track_only = true;
  job.seed = 5;
  run_job(job, silent_reporter());
  // The options, with the frame rate the run took (the frames state none),
  // then the [job] table: the build and the frames (no exemplar).
  JobOptions recorded = job;
  recorded.input.fps = Sequence::kDefaultFps;
  EXPECT_EQ(test::read_file(dir.path() / "out" / "job.toml"), job_record_toml(make_job_record(recorded, {1, 2})));
  const std::string text = test::read_file(dir.path() / "out" / "job.toml");
  EXPECT_TRUE(text.starts_with(job_toml(recorded))) << text;
  EXPECT_NE(text.find("\n[job]\nversion=\"" + version_line() + "\"\nexemplar-sha1=\"\"\nframes=\"1-2\"\n"),
            std::string::npos)
      << text;
  const JobRecord record = read_job_record(dir.file("out"));
  EXPECT_EQ(record.version, version_line());
  EXPECT_EQ(record.frames, (std::vector<int>{1, 2}));
  EXPECT_EQ(record.options.seed, 5u);
}

/// Keeps the warnings a run gives.
}  // namespace
}  // namespace fluidtex

namespace fluidtex {
namespace {

/// A frame is complete with its state or absent: when the state cannot be
/// written (here a folder is in its way; disk full or a read-only state/ are
/// the same), the atlas and mesh of that frame and of the frames in flight
/// behind it are removed again.
TEST(Pipeline, FrameWhoseStateFailsLeavesNoAtlasOrMesh) {
  test::TempDir dir;
  test::write_rotation_scene(dir.path(), 3, 8, "ex.png", 16);
  JobOptions job;
  job.input.pattern = dir.file("rotation.####.ply");
  job.exemplar = dir.file("ex.png");
  job.output.dir = dir.file("out");
  job.synthesis.atlas.size = 64;
  std::filesystem::create_directories(dir.path() / "out" / "state" / "patches.0002.bin");
  EXPECT_THROW(run_job(job, silent_reporter()), InternalError);
  const auto out = dir.path() / "out";
  EXPECT_TRUE(std::filesystem::exists(out / "atlas.0001.exr"));
  EXPECT_TRUE(std::filesystem::exists(out / "state" / "patches.0001.bin"));
  for (const char* name : {"atlas.0002.exr", "mesh.0002.obj", "atlas.0003.exr", "mesh.0003.obj"})
    EXPECT_FALSE(std::filesystem::exists(out / name)) << name;  // frame 3 may have been in flight
}

/// Keeps the warnings a run gives.
struct WarningLog : Reporter {
  std::vector<std::string> warnings;
  void warn(const std::string& message) override { warnings.push_back(message); }
};

TEST(Pipeline, LiquidThatGrowsFromASmallStartIsWarnedOfOnceUnlessTheRadiusIsGiven) {
  // A flat sheet spreading from 0.25 to 0.85 across in three frames (its
  // area 11.6 times the first's): the automatic radius comes from the first
  // frame, so the patches multiply. One warning says so and what to do.
  test::TempDir dir;
  const std::vector<double> sizes = {0.25, 0.45, 0.65, 0.85};
  const double fps = 24.0;
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    const double rate = i + 1 < sizes.size() ? (sizes[i + 1] / sizes[i] - 1.0) * fps : 0.0;
    const FrameMesh sheet = test::flat_grid(24, sizes[i], 0.0, 0.0, 0.0, [&](const Vec3& p) { return rate * p; });
    write_frame_ply(dir.file(FramePattern("sheet.####.ply").path(static_cast<int>(i) + 1)), sheet, fps);
  }
  JobOptions job;
  job.input.pattern = dir.file("sheet.####.ply");
  job.output.dir = dir.file("auto");
  job.synthesis.track_only = true;
  WarningLog log;
  run_job(job, log);
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_TRUE(log.warnings[0].starts_with("frame 4: the liquid's surface is 11.6 times frame 1's")) << log.warnings[0];
  EXPECT_NE(log.warnings[0].find("give --radius"), std::string::npos) << log.warnings[0];
  job.output.dir = dir.file("given");
  job.tracking.radius = 0.05;
  WarningLog quiet;
  run_job(job, quiet);
  EXPECT_TRUE(quiet.warnings.empty());
}

}  // namespace
}  // namespace fluidtex
