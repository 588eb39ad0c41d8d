#include "fluidtex/job/job_layout.h"

#include <filesystem>

#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/strings.h"

namespace fluidtex {

std::vector<std::string> frame_output_patterns(const JobOptions& options) {
  std::vector<std::string> patterns = {options.output.atlas(), options.output.mesh()};
  if (lower_extension(patterns[1]) == ".obj") patterns.push_back(material_pattern(patterns[1]));
  for (const std::string& map : {options.output.displacement(), options.output.normal()}) {
    if (!map.empty()) patterns.push_back(map);
  }
  for (const std::string& layer : options.synthesis.aov)
    patterns.push_back(options.output.dir + "/aov/" + layer + ".####.exr");
  return patterns;
}

std::string material_pattern(const std::string& obj_pattern) {
  return std::filesystem::path(obj_pattern).replace_extension(".mtl").string();
}

void remove_frame_outputs(const JobOptions& options, int frame) {
  std::error_code ec;
  for (const std::string& pattern : frame_output_patterns(options))
    std::filesystem::remove(FramePattern(pattern).path(frame), ec);
}

std::string state_pattern(const std::string& dir) { return dir + "/state/patches.####.bin"; }

std::string state_path(const std::string& dir, int frame) { return FramePattern(state_pattern(dir)).path(frame); }

std::size_t remove_interrupted_temporaries(const JobOptions& options,
                                           const std::function<bool(const std::string&)>& owned) {
  namespace fs = std::filesystem;
  const fs::path out(options.output.dir);
  std::size_t stale = 0;
  std::vector<fs::path> dirs = {out,
                                out / "state",
                                out / "aov",
                                out / "stats",
                                fs::path(options.output.atlas()).parent_path(),
                                fs::path(options.output.mesh()).parent_path()};
  for (const std::string& map : {options.output.displacement(), options.output.normal()}) {
    if (!map.empty()) dirs.push_back(fs::path(map).parent_path());
  }
  for (const fs::path& dir : dirs) stale += remove_stale_temporaries(dir.empty() ? "." : dir, owned);
  return stale;
}

}  // namespace fluidtex
