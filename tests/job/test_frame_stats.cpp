// stats.jsonl (job/frame_stats.h): the exact line, non-finite values and escaped
// keys, and the writer's rewrite and append.
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fluidtex/job/frame_stats.h"
#include "fluidtex/util/error.h"
#include "test_util.h"

namespace fluidtex {
namespace {

using test::list_dir;
using test::read_file;
using test::TempDir;

FrameStats sample_stats(int frame) {
  FrameStats s;
  s.frame = frame;
  s.vertices = 1234;
  s.faces = 2400;
  s.patches = {1, 2, 3, 4};
  s.seconds = {{"advect", 0.25}, {"synthesis", 1.5}, {"pack", 0.1}};
  s.uncovered_fraction = 0.003;
  s.extra = {{"packing_efficiency", 0.7}, {"texels_per_second", 1e20}};
  return s;
}

TEST(StatsJson, ExactLine) {
  EXPECT_EQ(to_json_line(sample_stats(7)),
            "{\"frame\":7,\"vertices\":1234,\"faces\":2400,"
            "\"patches\":{\"fading_in\":1,\"active\":2,\"fading_out_distorted\":3,"
            "\"fading_out_close\":4},"
            "\"seconds\":{\"advect\":0.25,\"synthesis\":1.5,\"pack\":0.1},"
            "\"uncovered_fraction\":0.003,"
            "\"packing_efficiency\":0.7,\"texels_per_second\":1e+20}");
}

TEST(StatsJson, NonFiniteIsNullAndKeysAreEscaped) {
  FrameStats s;
  s.frame = -1;
  s.uncovered_fraction = std::numeric_limits<double>::quiet_NaN();
  s.seconds = {{"a\"b\\c", std::numeric_limits<double>::infinity()}};
  s.extra = {{"tab\there\nnew\x01", -0.0}, {"small", 1.0 / 3.0}};
  EXPECT_EQ(to_json_line(s),
            "{\"frame\":-1,\"vertices\":0,\"faces\":0,"
            "\"patches\":{\"fading_in\":0,\"active\":0,\"fading_out_distorted\":0,"
            "\"fading_out_close\":0},"
            "\"seconds\":{\"a\\\"b\\\\c\":null},\"uncovered_fraction\":null,"
            "\"tab\\there\\nnew\\u0001\":-0,\"small\":0.3333333333333333}");
}

TEST(StatsWriter, AddRewritesAndAppendExistingKeepsLines) {
  TempDir dir;
  const std::string path = dir.file("stats.jsonl");
  {
    StatsWriter w(path);
    w.add(sample_stats(1));
    w.add(sample_stats(2));
    EXPECT_EQ(read_file(path), to_json_line(sample_stats(1)) + "\n" + to_json_line(sample_stats(2)) + "\n");
  }
  {
    StatsWriter w(path, /*append_existing=*/true);
    w.add(sample_stats(3));
    const auto lines = test::lines_of(read_file(path));
    ASSERT_EQ(lines.size(), 3u);
    EXPECT_EQ(lines[0], to_json_line(sample_stats(1)));
    EXPECT_EQ(lines[2], to_json_line(sample_stats(3)));
    // A resumed frame replaces its old line instead of listing it twice.
    FrameStats redo = sample_stats(2);
    redo.faces = 99;
    w.add(redo);
    const auto again = test::lines_of(read_file(path));
    ASSERT_EQ(again.size(), 3u);
    EXPECT_EQ(again[1], to_json_line(redo));
  }
  EXPECT_EQ(list_dir(dir.path()), (std::vector<std::string>{"stats.jsonl"}));
  {
    StatsWriter w(path);  // a fresh run starts a fresh file
    EXPECT_EQ(read_file(path), "");
    w.add(sample_stats(10));
    EXPECT_EQ(test::lines_of(read_file(path)).size(), 1u);
  }
  StatsWriter missing(dir.file("new/stats.jsonl"), true);  // nothing to resume from
  missing.add(sample_stats(0));
  EXPECT_EQ(test::lines_of(read_file(dir.file("new/stats.jsonl"))).size(), 1u);
}

}  // namespace
}  // namespace fluidtex
