#include "fluidtex/job/job_options.h"

#include <algorithm>
#include <filesystem>

#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/strings.h"
#include "fluidtex/util/version.h"

namespace fluidtex {

namespace {

std::string checked_pattern(const std::string& given, const std::string& fallback,
                            std::initializer_list<const char*> extensions, const char* option, bool tiles = false) {
  std::string pattern = given.empty() ? fallback : given;
  const FramePattern parsed(pattern);  // throws without a frame token
  if (parsed.has_udim() && !tiles)
    throw InputError(pattern, std::string(option) + ": <UDIM> names the tiles of a texture, not of a mesh");
  const std::string ext = lower_extension(pattern);
  for (const char* e : extensions) {
    if (ext == e) return pattern;
  }
  std::string known;
  for (const char* e : extensions) known += std::string(known.empty() ? "" : ", ") + e;
  throw InputError(pattern, std::string(option) + ": unsupported extension '" + ext + "' (use " + known + ")");
}

}  // namespace

std::string OutputOptions::atlas() const {
  return checked_pattern(atlas_pattern, dir + "/atlas.####.exr", {".exr", ".png", ".tif", ".tiff"}, "--atlas", true);
}

std::string OutputOptions::mesh() const {
  return checked_pattern(mesh_pattern, dir + "/mesh.####.obj", {".obj", ".ply"}, "--mesh");
}

// The layers are data, not colour: EXR keeps them linear (PNG and TIFF
// atlases are sRGB-encoded).
std::string JobOptions::layer_pattern(std::size_t layer) const {
  const FrameLayer& l = kFrameLayers[layer];
  if (l.option) {
    const std::string& given = output.layer_patterns[layer];
    return given.empty() ? std::string()
                         : checked_pattern(given, "", {".exr"}, ("--" + std::string(l.option)).c_str(), true);
  }
  const bool asked = std::find(synthesis.aov.begin(), synthesis.aov.end(), l.name) != synthesis.aov.end();
  const char* tiles = FramePattern(output.atlas()).has_udim() ? ".<UDIM>" : "";
  return asked ? output.dir + "/aov/" + l.name + ".####" + tiles + ".exr" : std::string();
}

void SynthesisJobOptions::validate() const {
  atlas.validate();
  check_options(*this);
}

void JobOptions::validate() const {
  input.validate();
  synthesis.validate();
  check_options(*this);
  if (exemplar.empty() && !synthesis.track_only) {
    throw InputError("", "-e/--exemplar: an exemplar image is required (or --track-only)");
  }
  if (output.dir.empty()) throw InputError("", "-o/--output: an output folder is required");
  const bool tiles = FramePattern(output.atlas()).has_udim();
  (void)output.mesh();
  for (std::size_t i = 0; i < kFrameLayerCount; ++i) {
    const std::string pattern = layer_pattern(i);
    if (pattern.empty() || !kFrameLayers[i].option) continue;
    const std::string option = "--" + std::string(kFrameLayers[i].option);
    if (synthesis.track_only) throw InputError("", option + ": a tracking step (--track-only) writes no atlas");
    if (FramePattern(pattern).has_udim() != tiles) {
      throw InputError(pattern, option + (tiles ? ": the atlas is in UDIM tiles (<UDIM> in --atlas); so is this layer: "
                                                  "put <UDIM> in its pattern too"
                                                : ": <UDIM> here but not in --atlas: the layers share the atlas's "
                                                  "tiles"));
    }
  }
  if (synthesis.compression != SynthesisJobOptions{}.compression && lower_extension(output.atlas()) != ".exr") {
    throw InputError("", "--compression: applies to EXR atlases, not " + output.atlas());
  }
  if (synthesis.layout != TextureLayout::Scanline && lower_extension(output.atlas()) != ".exr") {
    throw InputError("", std::string("--texture-layout ") + enum_name(synthesis.layout) +
                             ": tiled and MIP-mapped atlases are EXR, not " + output.atlas());
  }
  if (method == TexturingMethod::FlowMap) {
    if (output.resume) throw InputError("", "--resume: --method flowmap keeps no state to resume from");
    if (synthesis.track_only) throw InputError("", "--track-only: --method flowmap has no patches to track");
    if (output.debug_views) throw InputError("", "--debug-views: --method flowmap has no patches or disks to show");
  }
  if (output.resume && output.force) throw InputError("", "--force: replaces the job that --resume would continue");
  if (synthesis.track_only && output.keep_state == KeepState::Last) {
    throw InputError("", "--keep-state last: a tracking step (--track-only) keeps every state for fluidtex synth");
  }
}

std::vector<OptionRef> option_table(JobOptions& o) {
  std::vector<OptionRef> table;
  JobOptions::for_each_option(o,
                              [&](const OptionInfo& info, auto& field) { table.push_back(bind_option(info, field)); });
  return table;
}

std::string job_toml(const JobOptions& o) {
  JobOptions copy = o;  // the table binds mutable fields
  return "# " + version_line() + "\n" + format_toml(option_table(copy));
}

void apply_job_file(JobOptions& o, const std::string& path, const std::function<bool(const std::string&)>& skip,
                    std::vector<OptionRef> extra) {
  std::vector<ConfigEntry> entries = read_config_file(path);
  std::vector<OptionRef> table = option_table(o);
  table.insert(table.end(), extra.begin(), extra.end());
  const auto find = [&](const std::string& name) {
    return std::find_if(table.begin(), table.end(), [&](const OptionRef& r) { return name == r.info.name; });
  };
  // fluidtex 0.1 wrote its console settings into job.toml, and 0 for an
  // automatic option.
  std::erase_if(entries, [&](const ConfigEntry& e) {
    return (e.name == "verbose" || e.name == "quiet") && find(e.name) == table.end();
  });
  for (ConfigEntry& e : entries) {
    const auto ref = find(e.name);
    if (ref != table.end() && ref->automatic && e.values == std::vector<std::string>{"0"}) e.values = {"auto"};
  }
  apply_config(entries, table, path, skip);
}

JobOptions read_job_file(const std::string& path) {
  JobOptions o;
  apply_job_file(o, path, [](const std::string&) { return false; });
  return o;
}

JobOptions read_job_manifest(const std::string& run_dir) {
  namespace fs = std::filesystem;
  const std::string path = run_dir + "/job.toml";
  if (!fs::exists(path)) {
    throw InputError(path, "missing: not the output folder of a fluidtex run (or one made before job.toml existed)");
  }
  JobOptions o = read_job_file(path);
  if (o.output.dir.empty()) return o;
  const fs::path recorded = fs::absolute(o.output.dir).lexically_normal(),
                 here = fs::absolute(run_dir).lexically_normal();
  if (recorded == here) return o;
  const auto relocate = [&](std::string& pattern) {
    if (pattern.empty()) return;
    const fs::path inside = fs::absolute(pattern).lexically_normal().lexically_relative(recorded);
    if (!inside.empty() && *inside.begin() != "..") pattern = (here / inside).string();
  };
  relocate(o.output.atlas_pattern);
  relocate(o.output.mesh_pattern);
  for (std::string& layer : o.output.layer_patterns) relocate(layer);
  return o;
}

}  // namespace fluidtex
