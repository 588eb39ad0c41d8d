// The job's options table (job/job_options.h): one entry per option, the
// job.toml a run writes and eval reads back.
#include <gtest/gtest.h>

#include <set>

#include "fluidtex/io/sequence.h"
#include "fluidtex/job/job_options.h"
#include "fluidtex/job/job_record.h"
#include "fluidtex/job/pipeline.h"
#include "fluidtex/util/version.h"
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

}  // namespace
}  // namespace fluidtex
