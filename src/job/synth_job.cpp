#include "fluidtex/job/synth_job.h"

#include <algorithm>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>

#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/io/sequence.h"
#include "fluidtex/job/frame_stats.h"
#include "fluidtex/job/frame_texturing.h"
#include "fluidtex/job/job_layout.h"
#include "fluidtex/job/job_record.h"
#include "fluidtex/texture/atlas.h"
#include "fluidtex/tracking/tracker.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/timing.h"
#include "fluidtex/util/version.h"

namespace fluidtex {

namespace fs = std::filesystem;

std::string synth_stats_path(const std::string& dir, const std::vector<int>& frames) {
  std::string range = format_frame_range(frames);
  std::replace(range.begin(), range.end(), ',', '_');
  return (fs::path(dir) / "stats" / ("synth." + range + ".jsonl")).string();
}

namespace {

/// The job's options as synthesis runs them, once the record says the job
/// can be synthesised here (InputError naming job.toml otherwise).
JobOptions synthesis_job(const JobRecord& record, const SynthRequest& request) {
  const std::string& dir = request.dir;
  const std::string path = job_record_path(dir);
  if (record.version.empty()) throw InputError(path, "written by a fluidtex without job records: track it again");
  if (record.version != version_line()) {
    throw InputError(path, "the job was tracked by " + record.version + ", this is " + version_line() +
                               ": synthesise with the build that tracked it, or track again");
  }
  JobOptions options = record.options;
  if (!request.input.empty()) options.input.pattern = request.input;
  if (!request.velocity_vdb.empty()) options.input.velocity_vdb = request.velocity_vdb;
  if (!request.exemplar.empty()) options.exemplar = request.exemplar;
  if (options.method != TexturingMethod::Patches) {
    throw InputError(path, "--method " + std::string(to_string(options.method)) +
                               ": the job keeps no patch states to synthesise from (fluidtex run textures it)");
  }
  if (options.exemplar.empty()) {
    throw InputError(path, "the job has no exemplar: give the tracking step one (run --track-only -e EXEMPLAR)");
  }
  const std::string sha1 = file_sha1(options.exemplar, "exemplar");
  if (sha1 != record.exemplar_sha1) {
    throw InputError(options.exemplar, "the exemplar changed since the job was tracked (sha1 " + sha1 + ", the job's " +
                                           record.exemplar_sha1 + ")");
  }
  const std::string ocio = options.synthesis.color.config_file();
  const std::string ocio_sha1 = ocio.empty() ? std::string() : file_sha1(ocio, "OpenColorIO config");
  if (ocio_sha1 != record.ocio_sha1) {
    throw InputError(ocio.empty() ? path : ocio,
                     "the OpenColorIO config differs from the job's (sha1 " +
                         (ocio_sha1.empty() ? std::string("none") : ocio_sha1) + ", the job's " +
                         (record.ocio_sha1.empty() ? std::string("none") : record.ocio_sha1) + ")");
  }
  options.output.dir = dir;
  options.output.resume = false;
  options.synthesis.track_only = false;
  options.input.frames = format_frame_range(record.frames);  // the sequence as tracked (velocity differences)
  options.validate();
  check_output_paths(options);
  return options;
}

/// The output files of `frame` that a textured frame has (atlas, UV mesh
/// and material, AOVs; of UDIM tiles, 1001); with `every_tile`, every file
/// it may have (each UDIM tile).
std::vector<fs::path> frame_outputs(const JobOptions& options, int frame, bool every_tile = false) {
  std::vector<fs::path> files;
  for (const std::string& pattern : frame_output_patterns(options)) {
    const FramePattern fp(pattern);
    files.emplace_back(fp.first_file(frame));
    for (int tile = 1; every_tile && fp.has_udim() && tile < kMaxUdimTiles; ++tile)
      files.emplace_back(fp.path(frame, udim_number(tile)));
  }
  return files;
}

/// One frame on its way through synthesis.
struct SynthWork {
  std::size_t index = 0;  // in the sequence
  Clock::time_point started = Clock::now();
  std::shared_ptr<const FrameMesh> mesh;
  FrameStats stats;
};

}  // namespace

namespace {

/// The requested frames that need texturing, every one checked before
/// anything is written: InputError for a frame outside the job or without a
/// state (unless --prune-state removed it after texturing the frame).
std::vector<int> frames_to_synthesise(const JobRecord& record, const JobOptions& options,
                                      const std::vector<int>& wanted, const SynthRequest& request, Reporter& reporter) {
  std::vector<int> todo;
  for (int f : wanted) {
    if (!std::binary_search(record.frames.begin(), record.frames.end(), f)) {
      throw InputError(job_record_path(request.dir), "--frames: frame " + std::to_string(f) +
                                                         " is not one of the job's frames " +
                                                         format_frame_range(record.frames));
    }
    const std::string state = state_path(request.dir, f);
    if (fs::exists(state)) {
      todo.push_back(f);
      continue;
    }
    const std::vector<fs::path> outputs = frame_outputs(options, f);
    const bool written = std::all_of(outputs.begin(), outputs.end(), [](const fs::path& p) { return fs::exists(p); });
    if (request.prune_state && written) {
      reporter.verbose("frame " + std::to_string(f) + ": textured and its state pruned already");
      continue;
    }
    throw InputError(state, "missing: frame " + std::to_string(f) +
                                " was not tracked (run the tracking step, or finish it with run --resume)");
  }
  return todo;
}

/// Removes the temporaries an interrupted step left for this step's files
/// (its frames' outputs and its stats file): another machine's too, as a
/// re-run after a killed task lands anywhere on the farm.
void remove_own_temporaries(const JobOptions& options, const std::vector<int>& frames, const std::string& stats_path,
                            Reporter& reporter) {
  std::set<std::string> owned = {fs::path(stats_path).filename().string()};
  for (int f : frames) {
    for (const fs::path& p : frame_outputs(options, f, true)) owned.insert(p.filename().string());
  }
  if (const std::size_t stale =
          remove_interrupted_temporaries(options, [&](const std::string& name) { return owned.count(name) > 0; }))
    reporter.verbose("removed " + std::to_string(stale) + " temporary files of an interrupted step");
}

}  // namespace

JobSummary synth_job(const SynthRequest& request, Reporter& reporter) {
  const auto start = Clock::now();
  const JobRecord record = read_job_record(request.dir);
  JobOptions options = synthesis_job(record, request);
  options.output.provenance = settings_hash(record);
  const std::vector<int> wanted = request.frames.empty() ? record.frames : parse_frame_range(request.frames);
  const std::vector<int> todo = frames_to_synthesise(record, options, wanted, request, reporter);
  const Sequence sequence = Sequence(options.input).followed();  // read as the run read it
  std::string warning;
  const TextureSource source = load_texture_source(options, &warning);
  if (!warning.empty()) reporter.warn(warning);

  const std::string stats_path = synth_stats_path(request.dir, wanted);
  remove_own_temporaries(options, todo, stats_path, reporter);
  StatsWriter stats(stats_path, true);

  JobSummary summary;
  std::size_t next = 0;
  auto read = [&]() -> std::shared_ptr<SynthWork> {
    if (next == todo.size()) return nullptr;
    auto work = std::make_shared<SynthWork>();
    const auto at = std::lower_bound(sequence.frames().begin(), sequence.frames().end(), todo[next++]);
    work->index = static_cast<std::size_t>(at - sequence.frames().begin());
    work->stats.method = to_string(options.method);
    work->mesh = read_frame_mesh(sequence, work->index, work->stats, reporter);
    return work;
  };
  auto texture = [&](SynthWork& work) {
    const int frame = work.stats.frame;
    std::optional<Tracker> tracker;
    {
      const ScopedStage stage(work.stats.seconds, "state");
      const std::string state = state_path(request.dir, frame);
      tracker.emplace(Tracker::load(state, work.mesh, frame));
      check_state_settings(tracker->settings(), options, state);
    }
    work.stats.patches = count_states(tracker->patches());
    synthesize_frame(*tracker->surface(), tracker->patches(), tracker->settings().tracking, source, options, frame,
                     work.stats);
  };
  auto write = [&](SynthWork& work) {
    stats.add(work.stats);
    ++summary.frames;
    reporter.frame_done(frame_report("synth", work.stats, work.started, true));
    reporter.progress(summary.frames, todo.size(), "written");
  };
  run_frames(FrameStages<SynthWork>{.read = read, .track = [](SynthWork&) {}, .texture = texture, .write = write});

  // Pruned only now that every frame is written: a step killed before this
  // point is re-run as it was; one killed while pruning skips the frames it
  // pruned. The job's last state stays for run --resume.
  if (request.prune_state) {
    for (int f : todo) {
      if (f == record.frames.back()) continue;
      std::error_code ignored;
      fs::remove(state_path(request.dir, f), ignored);
    }
  }
  summary.seconds = seconds_since(start);
  return summary;
}

}  // namespace fluidtex
