// Helpers shared by the tests.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace fluidtex::test {

/// A fresh, empty folder under the system temp dir, removed on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  std::string str() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

/// Names of the entries in `dir` (not recursive), sorted.
std::vector<std::string> list_dir(const std::filesystem::path& dir);

/// Reads a whole file as bytes.
std::string read_file(const std::filesystem::path& path);

/// The lines of `text`, without their '\n'.
std::vector<std::string> lines_of(const std::string& text);

/// Writes bytes to a file.
void write_file(const std::filesystem::path& path, const std::string& bytes);

/// A small generated rotation scene in `dir` (`rotation.####.ply`, frames
/// 1..`frames` at `resolution` cells across) and, unless `exemplar` is empty,
/// a generated gravel exemplar of `exemplar_size`² pixels (`exemplar_seed`)
/// as `dir/exemplar`: the input of most end-to-end tests.
void write_rotation_scene(const std::filesystem::path& dir, int frames, int resolution,
                          const std::string& exemplar = "ex.png", int exemplar_size = 32,
                          std::uint64_t exemplar_seed = 1);

/// Runs the fluidtex executable with `args` (shell-quoted by the caller),
/// capturing stdout+stderr into `output`; returns the exit code.
int run_fluidtex(const std::string& args, std::string* output = nullptr);

}  // namespace fluidtex::test
