// write_atomically (util/atomic_file.h): the target holds either its old or
// its whole new content, and no temporary file is left behind.
#include <gtest/gtest.h>

#include <fstream>
#include <stdexcept>

#include <unistd.h>

#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/error.h"
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

TEST(AtomicFile, AFullDiskIsNamedInTheError) {
  // /dev/full fails every write with ENOSPC, as a full output disk does.
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  std::ofstream out("/dev/full", std::ios::binary);
  out << std::string(1 << 16, 'x');  // more than the stream buffers
  try {
    close_written(out, "/out/frame.bin");
    FAIL() << "a write to a full disk passed";
  } catch (const InternalError& e) {
    EXPECT_STREQ(e.what(), "/out/frame.bin: cannot write file: No space left on device");
  }
}

TEST(AtomicFile, AFolderThatCannotBeWrittenIsNamedInTheError) {
  test::TempDir dir;
  std::ofstream out(dir.path() / "missing" / "x.bin", std::ios::binary);
  try {
    close_written(out, dir.path() / "x.bin");
    FAIL() << "a stream that never opened passed";
  } catch (const InternalError& e) {
    EXPECT_EQ(std::string(e.what()),
              (dir.path() / "x.bin").string() + ": cannot write file: No such file or directory");
  }
}

TEST(AtomicFile, StaleTemporariesOfThisMachineGoAndOtherMachinesOnlyWhenOwned) {
  test::TempDir dir;
  const std::string dead = "999999999";  // above any pid Linux hands out
  const std::string live = std::to_string(::getpid());
  // The name temporary_sibling gives carries this machine's host.
  const std::string own = temporary_sibling(dir.path() / "atlas.0001.exr").filename().string();
  EXPECT_NE(own.find("-" + host_name() + ".exr"), std::string::npos) << own;
  const std::vector<std::string> names = {
      ".atlas.0001.tmp-" + dead + "-0-" + host_name() + ".exr",  // this machine, writer gone
      ".atlas.0002.tmp-" + live + "-0-" + host_name() + ".exr",  // this machine, writer alive
      ".atlas.0003.tmp-" + dead + "-4.exr",                      // fluidtex 0.1 name: this machine
      ".atlas.0004.tmp-" + dead + "-0-othernode.exr",            // another machine
      ".atlas.0005.tmp-" + dead + "-0-othernode.exr",            // another machine, target owned
      ".job.tmp-x-1.toml",                                       // not a temporary's name
      "atlas.0001.exr"};
  for (const std::string& n : names) test::write_file(dir.path() / n, "x");
  const auto owned = [](const std::string& target) { return target == "atlas.0005.exr"; };
  EXPECT_EQ(remove_stale_temporaries(dir.path(), owned), 3u);
  EXPECT_EQ(test::list_dir(dir.path()),
            (std::vector<std::string>{".atlas.0002.tmp-" + live + "-0-" + host_name() + ".exr",
                                      ".atlas.0004.tmp-" + dead + "-0-othernode.exr", ".job.tmp-x-1.toml",
                                      "atlas.0001.exr"}));
}

}  // namespace
}  // namespace fluidtex
