#include "fluidtex/job/job_record.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <set>

#include <OpenImageIO/hash.h>

#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/job/job_layout.h"
#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/strings.h"
#include "fluidtex/util/version.h"

namespace fluidtex {

namespace fs = std::filesystem;

namespace {

/// A path as a resumed run compares it: absolute, normalised.
std::string comparable_path(const std::string& path) {
  if (path.empty()) return path;
  return fs::absolute(fs::path(path)).lexically_normal().string();
}

bool is_path(const OptionRef& ref) {
  return ref.info.role == OptionRole::OutputPath || ref.info.role == OptionRole::InputPath;
}

/// The options as --resume compares them: the output patterns resolved
/// against the job's folder (an empty pattern is the default name there).
JobOptions with_resolved_outputs(JobOptions o) {
  o.output.atlas_pattern = o.output.atlas();
  o.output.mesh_pattern = o.output.mesh();
  return o;
}

std::string quoted(const std::string& text) { return "'" + text + "'"; }

/// What `sha1sum` prints: the digest in lower-case hex.
std::string lower_case_digest(OIIO::SHA1& sha) {
  std::string digest = sha.digest();
  std::transform(digest.begin(), digest.end(), digest.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return digest;
}

}  // namespace

std::string file_sha1(const std::string& path, const std::string& what) {
  require_regular_file(path, what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open file");
  OIIO::SHA1 sha;
  std::vector<char> buffer(1 << 20);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    sha.append(buffer.data(), static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) throw InputError(path, "read error");
  return lower_case_digest(sha);
}

std::string settings_hash(const JobRecord& record) {
  JobOptions o = record.options;  // option_table binds mutable fields
  OIIO::SHA1 sha;
  const auto add = [&](const std::string& key, const std::string& value) {
    const std::string line = key + "=" + value + "\n";
    sha.append(line.data(), line.size());
  };
  add("version", record.version);
  add("exemplar-sha1", record.exemplar_sha1);
  if (!record.ocio_sha1.empty()) add("ocio-sha1", record.ocio_sha1);
  for (const OptionRef& ref : option_table(o)) {
    if (ref.info.role == OptionRole::Method) add(ref.info.name, ref.text());
  }
  return lower_case_digest(sha);
}

std::string job_record_path(const std::string& run_dir) { return (fs::path(run_dir) / "job.toml").string(); }

JobRecord make_job_record(const JobOptions& options, const std::vector<int>& frames) {
  JobRecord record;
  record.options = options;
  record.options.output.resume = false;
  record.options.output.force = false;
  // Absolute paths: a synth step or a resume may start in another folder.
  for (const OptionRef& ref : option_table(record.options)) {
    if (is_path(ref) && !ref.text().empty()) ref.set({comparable_path(ref.text())});
  }
  record.version = version_line();
  if (!options.exemplar.empty()) record.exemplar_sha1 = file_sha1(options.exemplar, "exemplar");
  const std::string ocio = options.synthesis.color.config_file();
  if (!ocio.empty()) record.ocio_sha1 = file_sha1(ocio, "OpenColorIO config");
  record.frames = frames;
  return record;
}

std::string job_record_toml(const JobRecord& record) {
  namespace d = option_detail;
  return job_toml(record.options) +
         "\n# The job: the build that made it, the exemplar's content (sha1sum) and the frames it covers.\n"
         "# fluidtex run --resume and fluidtex synth refuse to continue a job that differs.\n"
         "[job]\n"
         "version=" +
         d::toml_string("version", record.version) +
         "\nexemplar-sha1=" + d::toml_string("exemplar-sha1", record.exemplar_sha1) +
         "\nframes=" + d::toml_string("frames", format_frame_range(record.frames)) + "\n" +
         (record.ocio_sha1.empty() ? std::string()
                                   : "ocio-sha1=" + d::toml_string("ocio-sha1", record.ocio_sha1) + "\n") +
         (record.exemplar_size ? "# Scene units one exemplar tile spans on the surface.\nexemplar-size=" +
                                     format_number(*record.exemplar_size) + "\n"
                               : std::string());
}

JobRecord read_job_record(const std::string& run_dir) {
  const std::string path = job_record_path(run_dir);
  std::error_code ec;
  if (fs::is_regular_file(path, ec) && fs::file_size(path, ec) == 0)
    throw InputError(path,
                     "empty: not a job record (the run that wrote it was cut off: run the job again, with --force)");
  JobRecord record;
  record.options = read_job_manifest(run_dir);
  for (const ConfigEntry& e : read_config_file(path, "job")) {
    const std::string value = e.values.size() == 1 ? e.values[0] : std::string();
    if (e.values.size() != 1) throw InputError(path, "[job] " + e.name + ": expected one value");
    if (e.name == "version") {
      record.version = value;
    } else if (e.name == "exemplar-sha1") {
      record.exemplar_sha1 = value;
    } else if (e.name == "ocio-sha1") {
      record.ocio_sha1 = value;
    } else if (e.name == "exemplar-size") {
      const double size = [&] {
        try {
          return option_detail::parse_number("exemplar-size", value);
        } catch (const InputError&) {
          return 0.0;  // refused below, naming job.toml
        }
      }();
      if (!(size > 0.0) || !std::isfinite(size))
        throw InputError(path, "[job] exemplar-size: '" + value + "' is not a length > 0");
      record.exemplar_size = size;
    } else if (e.name == "frames") {
      try {
        record.frames = parse_frame_range(value);
      } catch (const InputError& err) {
        throw InputError(path, "[job] frames: " + err.problem());
      }
    } else {
      throw InputError(path, "unknown [job] key '" + e.name + "'");
    }
  }
  return record;
}

void check_state_settings(const TrackerSettings& state, const JobOptions& job, const std::string& state_path) {
  JobOptions a = job, b = job;  // the tables bind mutable fields
  b.tracking = state.tracking;
  b.advection = state.advection;
  b.patch_motion = state.motion;
  b.seed = state.seed;
  b.no_coverage_check = !state.coverage_aware;
  const std::vector<OptionRef> ta = option_table(a), tb = option_table(b);
  for (std::size_t i = 0; i < ta.size(); ++i) {
    const std::string va = ta[i].text(), vb = tb[i].text();
    if (va == vb || (ta[i].automatic && va == "auto")) continue;
    throw InputError(state_path, "--" + std::string(ta[i].info.name) + " is " + quoted(va) +
                                     " in the job, but this state was tracked with " + quoted(vb) +
                                     " (job.toml edited after tracking, or a state of another job?): track "
                                     "again, or give the job its value back");
  }
}

void check_resumable(const JobRecord& job, const JobRecord& given) {
  const std::string path = job_record_path(given.options.output.dir);
  const std::string restart = " (or --force to replace the job)";
  if (job.version.empty()) {
    throw InputError(path, "written by a fluidtex without job records: --resume cannot check it" + restart);
  }
  if (job.version != given.version) {
    throw InputError(path, "the job was made by " + job.version + ", this is " + given.version +
                               ": resume it with that build" + restart);
  }
  JobOptions a = job.options, b = given.options;  // the tables bind mutable fields
  a.output.dir = b.output.dir;                    // the job is the one in this folder, however it is spelled
  a = with_resolved_outputs(a), b = with_resolved_outputs(b);
  const std::vector<OptionRef> ta = option_table(a), tb = option_table(b);
  for (std::size_t i = 0; i < ta.size(); ++i) {
    const OptionRole role = ta[i].info.role;
    if (role == OptionRole::InputPath || role == OptionRole::Free) continue;
    const std::string name = ta[i].info.name;
    const bool as_path = role == OptionRole::OutputPath;
    const std::string va = as_path ? comparable_path(ta[i].text()) : ta[i].text();
    const std::string vb = as_path ? comparable_path(tb[i].text()) : tb[i].text();
    if (va == vb) continue;
    std::string problem = "--" + name;
    problem += " differs from the job's: " + quoted(vb) + " given, " + quoted(va) + " in the job" + restart;
    throw InputError(path, problem);
  }
  if (job.exemplar_sha1 != given.exemplar_sha1) {
    const std::string problem = job.exemplar_sha1.empty() ? "the job has no exemplar"
                                : given.exemplar_sha1.empty()
                                    ? "the job was made with one (" + job.options.exemplar + ")"
                                    : "its content differs from the job's (sha1 " + given.exemplar_sha1 +
                                          ", the job's " + job.exemplar_sha1 + ")";
    throw InputError(path, "--exemplar: " + problem + restart);
  }
  if (job.ocio_sha1 != given.ocio_sha1) {
    throw InputError(path, "--ocio-config: the OpenColorIO config differs from the job's (sha1 " +
                               (given.ocio_sha1.empty() ? std::string("none") : given.ocio_sha1) + ", the job's " +
                               (job.ocio_sha1.empty() ? std::string("none") : job.ocio_sha1) + ")" + restart);
  }
  const std::size_t n = std::min(job.frames.size(), given.frames.size());
  if (!std::equal(job.frames.begin(), job.frames.begin() + static_cast<std::ptrdiff_t>(n), given.frames.begin())) {
    throw InputError(path, "--frames: " + format_frame_range(given.frames) + " does not continue the job's frames " +
                               format_frame_range(job.frames) +
                               " (a resume keeps their first frame and step; fluidtex synth textures a part of them)");
  }
}

std::vector<fs::path> existing_job_outputs(const JobOptions& options) {
  const fs::path out(options.output.dir);
  std::set<fs::path> files;
  std::error_code ec;
  const auto add_file = [&](const fs::path& p) {
    if (fs::exists(fs::symlink_status(p, ec))) files.insert(p);
  };
  const auto add_pattern = [&](const std::string& pattern) {
    const FramePattern fp(pattern);
    for (int f : fp.discover()) {
      for (const fs::path p : fp.files(f)) {
        if (!fs::is_directory(fs::symlink_status(p, ec))) files.insert(p);  // outputs are files
      }
    }
  };
  add_file(out / "job.toml");
  add_file(out / "stats.jsonl");
  for (const auto& entry : fs::directory_iterator(out / "stats", ec)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with("synth.") && name.ends_with(".jsonl")) files.insert(entry.path());
  }
  add_pattern(state_pattern(options.output.dir));
  // Every AOV layer, not only this job's: an earlier job may have had others.
  JobOptions all_layers = options;
  all_layers.synthesis.aov = option_detail::split_choices(aov_layer_names());
  for (const std::string& pattern : frame_output_patterns(all_layers)) add_pattern(pattern);
  for (const std::string& pattern : debug_view_patterns(out.string())) add_pattern(pattern);
  for (const char* name : {"metrics.jsonl", "summary.json", "report.html"}) add_file(out / "eval" / name);
  add_pattern((out / "eval/preview.####.png").string());
  add_pattern((out / "preview/frame.####.png").string());
  add_file(out / "preview/sheet.png");
  return {files.begin(), files.end()};
}

std::size_t claim_output_folder(const JobOptions& options) {
  std::vector<fs::path> files = existing_job_outputs(options);
  if (fs::exists(job_record_path(options.output.dir))) {
    // The earlier job may have put its atlases or meshes elsewhere.
    try {
      JobOptions earlier = read_job_manifest(options.output.dir);
      earlier.output.dir = options.output.dir;
      for (fs::path& p : existing_job_outputs(earlier)) files.push_back(std::move(p));
    } catch (const InputError&) {
      // An unreadable job.toml: its own patterns are unknown; the defaults were listed.
    }
  }
  std::sort(files.begin(), files.end());
  files.erase(std::unique(files.begin(), files.end()), files.end());
  // The job's inputs are never its outputs (an OBJ sequence named like the
  // UV meshes, in the output folder): refused rather than replaced.
  std::error_code ec;
  const auto canonical = [&](const fs::path& p) {
    const fs::path c = fs::weakly_canonical(p, ec);
    return ec ? fs::absolute(p).lexically_normal() : c;
  };
  std::set<fs::path> inputs;
  const FramePattern input(options.input.pattern);
  for (int f : input.discover()) inputs.insert(canonical(input.path(f)));
  if (!options.exemplar.empty()) inputs.insert(canonical(options.exemplar));
  for (const fs::path& f : files) {
    if (inputs.count(canonical(f))) {
      throw InputError(f.string(),
                       "an input of the job is also one of its outputs (choose another -o, --atlas or --mesh)");
    }
  }
  if (files.empty()) return 0;
  if (!options.output.force) {
    const fs::path record = job_record_path(options.output.dir);
    const fs::path named = std::binary_search(files.begin(), files.end(), record) ? record : files.front();
    const std::string more = files.size() > 1 ? " and " + std::to_string(files.size() - 1) + " more files" : "";
    throw InputError(options.output.dir, "holds the outputs of an earlier job (" + named.string() + more +
                                             "): --resume continues it, --force replaces it");
  }
  std::size_t removed = 0;
  std::set<fs::path> folders;
  for (const fs::path& f : files) {
    std::error_code ec;
    if (fs::remove(f, ec)) ++removed;
    if (ec) throw InternalError(f.string() + ": --force cannot remove it: " + ec.message());
    folders.insert(f.parent_path());
  }
  for (const fs::path& dir : folders) {
    std::error_code ignored;
    if (dir != fs::path(options.output.dir)) fs::remove(dir, ignored);  // only when empty
  }
  return removed;
}

}  // namespace fluidtex
