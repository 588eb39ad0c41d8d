// write_atomically (util/atomic_file.h): the target holds either its old or
// its whole new content, and no temporary file is left behind.
#include <gtest/gtest.h>

#include <fstream>
#include <stdexcept>

#include "fluidtex/util/atomic_file.h"
#include "test_util.h"

namespace fluidtex {
namespace {

namespace fs = std::filesystem;

TEST(AtomicFile, WritesThroughATemporaryAndCreatesFolders) {
  test::TempDir dir;
  const fs::path target = dir.path() / "a" / "b" / "out.txt";
  fs::path seen;
  write_atomically(target, [&](const fs::path& tmp) {
    seen = tmp;
    EXPECT_EQ(tmp.parent_path(), target.parent_path());
    EXPECT_EQ(tmp.extension(), ".txt");  // writers pick the format from it
    EXPECT_FALSE(fs::exists(target));
    std::ofstream(tmp) << "hello";
  });
  EXPECT_EQ(test::read_file(target), "hello");
  EXPECT_FALSE(fs::exists(seen));
  write_text_atomically(target, "again");
  EXPECT_EQ(test::read_file(target), "again");
  EXPECT_EQ(test::list_dir(target.parent_path()), std::vector<std::string>{"out.txt"});
}

TEST(AtomicFile, AFailedWriteKeepsTheOldFileAndLeavesNoTemporary) {
  test::TempDir dir;
  const fs::path target = dir.path() / "out.exr";
  write_text_atomically(target, "old");
  EXPECT_THROW(write_atomically(target,
                                [](const fs::path& tmp) {
                                  std::ofstream(tmp) << "half";
                                  throw std::runtime_error("disk full");
                                }),
               std::runtime_error);
  EXPECT_EQ(test::read_file(target), "old");
  EXPECT_EQ(test::list_dir(dir.path()), std::vector<std::string>{"out.exr"});
  EXPECT_NE(temporary_sibling(target), temporary_sibling(target));  // unique names
}

}  // namespace
}  // namespace fluidtex
