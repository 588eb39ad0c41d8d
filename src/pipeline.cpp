#include "fluidtex/pipeline.h"

#include <chrono>
#include <filesystem>

#include "fluidtex/error.h"
#include "fluidtex/frame_pattern.h"
#include "fluidtex/image_io.h"
#include "fluidtex/sequence.h"
#include "fluidtex/stats.h"

namespace fluidtex {

namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

std::string checked_pattern(const std::string& given, const std::string& fallback,
                            std::initializer_list<const char*> extensions, const char* option) {
  const std::string pattern = given.empty() ? fallback : given;
  FramePattern parsed(pattern);  // throws without a frame token
  const std::string ext = lower_extension(pattern);
  for (const char* e : extensions) {
    if (ext == e) return pattern;
  }
  std::string known;
  for (const char* e : extensions) known += std::string(known.empty() ? "" : ", ") + e;
  throw InputError(pattern, std::string(option) + ": unsupported extension '" + ext +
                                "' (use " + known + ")");
}

}  // namespace

std::string OutputOptions::atlas() const {
  return checked_pattern(atlas_pattern, dir + "/atlas.####.exr", {".exr", ".png", ".tif", ".tiff"},
                         "--atlas");
}

std::string OutputOptions::mesh() const {
  return checked_pattern(mesh_pattern, dir + "/mesh.####.obj", {".obj", ".ply"}, "--mesh");
}

void JobOptions::validate() const {
  input.validate();
  tracking.validate();
  if (output.dir.empty()) throw InputError("", "-o/--output: an output folder is required");
  (void)output.atlas();
  (void)output.mesh();
  if (threads < 0) throw InputError("", "--threads must be >= 0 (0 = all cores)");
}

JobSummary run_job(const JobOptions& options, Reporter& reporter) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  options.validate();
  const Sequence sequence(options.input);
  if (!options.exemplar.empty()) (void)read_image(options.exemplar);  // fail early when unreadable

  // The tracking and synthesis stages are built on top of this loop; until
  // they land, a run validates and measures every frame of the input.
  reporter.warn("patch tracking and texture synthesis are not in this build yet: "
                "this run validates the input and writes stats.jsonl only");
  StatsWriter stats(options.output.dir + "/stats.jsonl");
  for (std::size_t i = 0; i < sequence.size(); ++i) {
    reporter.progress(i, sequence.size(), "read");
    const auto t0 = Clock::now();
    CleanReport cleaned;
    const FrameMesh mesh = sequence.load(i, &cleaned);
    if (cleaned.changed()) {
      reporter.verbose(sequence.path_of(sequence.frames()[i]) + ": " + cleaned.summary());
    }
    FrameStats frame;
    frame.frame = sequence.frames()[i];
    frame.vertices = mesh.num_vertices();
    frame.faces = mesh.num_faces();
    frame.seconds.emplace_back("read", std::chrono::duration<double>(Clock::now() - t0).count());
    frame.uncovered_fraction = 1.0;  // no patch covers anything yet
    stats.add(frame);
  }
  reporter.progress(sequence.size(), sequence.size(), "done");
  JobSummary summary;
  summary.frames = sequence.size();
  summary.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return summary;
}

}  // namespace fluidtex
