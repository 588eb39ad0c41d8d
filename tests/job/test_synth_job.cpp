// synth (job/synth_job.h): frames synthesised from a tracking step's states
// in any split and order equal one run byte for byte, from pruned states
// too, and a synth step removes only its own temporaries.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "farm_fixtures.h"
#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/job/synth_job.h"
#include "test_util.h"

namespace fluidtex {
namespace {

namespace fs = std::filesystem;
using namespace test::farm;
using test::run_fluidtex;

TEST(SynthJob, TrackThenSynthInAnySplitEqualsOneRun) {
  test::TempDir dir;
  const std::string run = scene(dir);
  std::string out;
  ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file("full")), &out), 0) << out;
  // Chunks as array tasks would run them: one, two, and three out of order.
  const std::vector<std::pair<std::string, std::vector<std::string>>> splits = {
      {"one", {""}}, {"two", {"1-3", "4-6"}}, {"three", {"5-6", "1-2", "3-4"}}};
  for (const auto& [name, chunks] : splits) {
    SCOPED_TRACE(name);
    ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file(name)) + " --track-only", &out), 0) << out;
    for (const std::string& c : chunks) {
      ASSERT_EQ(run_fluidtex("synth -q -o " + q(dir.file(name)) + (c.empty() ? "" : " --frames " + c), &out), 0) << out;
    }
    expect_same_files(dir.path() / "full", dir.path() / name, frame_files());
    // Each chunk wrote its own stats file, one line per frame.
    for (const std::string& c : chunks) {
      const std::vector<int> frames = c.empty() ? parse_frame_range("1-6") : parse_frame_range(c);
      const std::string stats = test::read_file(synth_stats_path(dir.file(name), frames));
      EXPECT_EQ(std::count(stats.begin(), stats.end(), '\n'), static_cast<long>(frames.size())) << stats;
    }
  }
}

TEST(SynthJob, PrunedStatesStillResumeAndSynthesise) {
  test::TempDir dir;
  const std::string run = scene(dir);
  std::string out;
  ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file("full")), &out), 0) << out;
  // run --keep-state last: one state at a time, and --resume carries on.
  ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file("last")) + " --frames 1-4 --keep-state last", &out), 0) << out;
  EXPECT_EQ(test::list_dir(dir.path() / "last" / "state"), std::vector<std::string>{"patches.0004.bin"});
  ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file("last")) + " --resume --keep-state last", &out), 0) << out;
  EXPECT_EQ(test::list_dir(dir.path() / "last" / "state"), std::vector<std::string>{"patches.0006.bin"});
  std::vector<std::string> outputs;
  for (const std::string& n : frame_files()) {
    if (!n.starts_with("state/")) outputs.push_back(n);
  }
  expect_same_files(dir.path() / "full", dir.path() / "last", outputs);
  // synth --prune-state: the textured frames' states go, the job's last
  // stays; a re-run (a task killed while pruning) skips them; the job resumes.
  ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file("pruned")) + " --frames 1-4 --track-only", &out), 0) << out;
  ASSERT_EQ(run_fluidtex("synth -q -o " + q(dir.file("pruned")) + " --frames 1-4 --prune-state", &out), 0) << out;
  EXPECT_EQ(test::list_dir(dir.path() / "pruned" / "state"), std::vector<std::string>{"patches.0004.bin"});
  ASSERT_EQ(run_fluidtex("synth -q -o " + q(dir.file("pruned")) + " --frames 1-4 --prune-state", &out), 0) << out;
  EXPECT_EQ(run_fluidtex("synth -q -o " + q(dir.file("pruned")) + " --frames 1-4", &out), 2) << out;
  ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file("pruned")) + " --track-only --resume", &out), 0) << out;
  ASSERT_EQ(run_fluidtex("synth -q -o " + q(dir.file("pruned")) + " --frames 5-6", &out), 0) << out;
  expect_same_files(dir.path() / "full", dir.path() / "pruned", outputs);
  // A tracking step keeps every state.
  EXPECT_EQ(run_fluidtex(run + "-o " + q(dir.file("x")) + " --track-only --keep-state last", &out), 2) << out;
}

TEST(SynthJob, ASynthStepRemovesOnlyItsOwnFilesTemporaries) {
  test::TempDir dir;
  const std::string run = scene(dir);
  std::string out;
  ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file("job")) + " --track-only", &out), 0) << out;
  // A task killed on another machine left temporaries for frames 2 and 5.
  const fs::path job = dir.path() / "job";
  test::write_file(job / ".atlas.0002.tmp-999999999-0-deadnode.exr", "half");
  test::write_file(job / ".atlas.0005.tmp-999999999-0-deadnode.exr", "half");
  ASSERT_EQ(run_fluidtex("synth -q -o " + q(job.string()) + " --frames 1-3", &out), 0) << out;
  EXPECT_FALSE(fs::exists(job / ".atlas.0002.tmp-999999999-0-deadnode.exr"));
  EXPECT_TRUE(fs::exists(job / ".atlas.0005.tmp-999999999-0-deadnode.exr"));  // another task's frame
  ASSERT_EQ(run_fluidtex("synth -q -o " + q(job.string()) + " --frames 4-6", &out), 0) << out;
  EXPECT_FALSE(fs::exists(job / ".atlas.0005.tmp-999999999-0-deadnode.exr"));
}

}  // namespace
}  // namespace fluidtex
