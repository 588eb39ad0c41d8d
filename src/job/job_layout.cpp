#include "fluidtex/job/job_layout.h"

#include <filesystem>

#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/strings.h"

namespace fluidtex {

std::vector<FrameOutput> labelled_frame_outputs(const JobOptions& options) {
  std::vector<FrameOutput> outputs = {{options.output.atlas(), "--atlas"}, {options.output.mesh(), "--mesh"}};
  if (lower_extension(options.output.mesh()) == ".obj")
    outputs.push_back({material_pattern(options.output.mesh()), "the material of --mesh"});
  for (std::size_t i = 0; i < kFrameLayerCount; ++i) {
    const FrameLayer& layer = kFrameLayers[i];
    std::string pattern = options.layer_pattern(i);
    if (!pattern.empty())
      outputs.push_back(
          {std::move(pattern), layer.option ? "--" + std::string(layer.option) : "--aov " + std::string(layer.name)});
  }
  return outputs;
}

std::vector<std::string> frame_output_patterns(const JobOptions& options) {
  std::vector<std::string> patterns;
  for (const FrameOutput& o : labelled_frame_outputs(options)) patterns.push_back(o.pattern);
  return patterns;
}

std::string material_pattern(const std::string& obj_pattern) {
  return std::filesystem::path(obj_pattern).replace_extension(".mtl").string();
}

void remove_frame_outputs(const JobOptions& options, int frame) {
  std::vector<std::string> patterns = frame_output_patterns(options);
  if (options.output.debug_views)
    for (std::string& pattern : debug_view_patterns(options.output.dir)) patterns.push_back(std::move(pattern));
  std::error_code ec;
  for (const std::string& pattern : patterns) {
    for (const std::string& file : FramePattern(pattern).files(frame)) std::filesystem::remove(file, ec);
  }
}

std::vector<std::string> debug_view_patterns(const std::string& dir) {
  return {dir + "/debug/patches.####.ply", dir + "/debug/disks.####.ply"};
}

std::string state_pattern(const std::string& dir) { return dir + "/state/patches.####.bin"; }

std::string state_path(const std::string& dir, int frame) { return FramePattern(state_pattern(dir)).path(frame); }

std::size_t remove_interrupted_temporaries(const JobOptions& options,
                                           const std::function<bool(const std::string&)>& owned) {
  namespace fs = std::filesystem;
  const fs::path out(options.output.dir);
  std::size_t stale = 0;
  std::vector<fs::path> dirs = {out, out / "state", out / "aov", out / "stats"};
  for (const std::string& pattern : frame_output_patterns(options)) dirs.push_back(fs::path(pattern).parent_path());
  for (const fs::path& dir : dirs) stale += remove_stale_temporaries(dir.empty() ? "." : dir, owned);
  return stale;
}

void check_output_paths(const JobOptions& options) {
  namespace fs = std::filesystem;
  // Each file as frame 1 (tile 1001) of its pattern, absolute: `a.####.exr`
  // and `a.%04d.exr` are one file.
  auto file_of = [](const std::string& pattern) {
    return fs::absolute(FramePattern(pattern).first_file(1)).lexically_normal().string();
  };
  std::vector<std::pair<std::string, std::string>> outputs;  // file, what writes it
  for (const FrameOutput& o : labelled_frame_outputs(options)) outputs.emplace_back(file_of(o.pattern), o.what);
  outputs.emplace_back(file_of(state_pattern(options.output.dir)), "the state files");
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (outputs[i].first == outputs[j].first)
        throw InputError(outputs[i].first, outputs[j].second + " and " + outputs[i].second +
                                               " would write the same file: give them different patterns");
    }
  }
  std::vector<std::pair<std::string, std::string>> inputs = {{file_of(options.input.pattern), "the input frames"}};
  if (!options.exemplar.empty())
    inputs.emplace_back(fs::absolute(options.exemplar).lexically_normal().string(), "the exemplar");
  for (const auto& [file, what] : outputs) {
    for (const auto& [in, in_what] : inputs) {
      if (file != in) continue;
      std::string problem = what;
      problem += " would overwrite " + in_what + ": write it elsewhere";
      throw InputError(file, problem);
    }
  }
}

}  // namespace fluidtex
