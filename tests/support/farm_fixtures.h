// A small job for the farm tests (test_synth_job, test_job_record,
// test_pipeline): the rotation scene, the run command over it, and the
// files two runs must share byte for byte.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "fluidtex/io/frame_pattern.h"
#include "test_util.h"

namespace fluidtex::test::farm {

inline std::string q(const std::string& s) { return "'" + s + "'"; }

constexpr int kFrames = 6;

/// The settings of the tests' jobs (a test changes them in place of these).
inline const std::string kSettings = "--atlas-size 128 --seed 3 ";

/// The rotation scene of kFrames frames in `dir` and the start of a run
/// command over it without the settings and -o.
inline std::string scene_run(const test::TempDir& dir) {
  write_rotation_scene(dir.path(), kFrames, 16);
  return "run -q -i " + q(dir.file("rotation.####.ply")) + " -e " + q(dir.file("ex.png")) + " --aov weight ";
}

/// The same, with the settings.
inline std::string scene(const test::TempDir& dir) { return scene_run(dir) + kSettings; }

/// The files of every frame that must be identical between two folders.
inline std::vector<std::string> frame_files(int frames = kFrames) {
  std::vector<std::string> names;
  for (int f = 1; f <= frames; ++f) {
    for (const char* p :
         {"atlas.####.exr", "mesh.####.obj", "mesh.####.mtl", "aov/weight.####.exr", "state/patches.####.bin"})
      names.push_back(FramePattern(p).path(f));
  }
  return names;
}

inline void expect_same_files(const std::filesystem::path& a, const std::filesystem::path& b,
                              const std::vector<std::string>& names) {
  for (const std::string& n : names) {
    const std::string x = read_file(a / n), y = read_file(b / n);
    EXPECT_FALSE(x.empty()) << n;
    EXPECT_TRUE(x == y) << n << " differs between " << a << " and " << b;
  }
}

}  // namespace fluidtex::test::farm
