#include "fluidtex/job/pipeline.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numeric>
#include <optional>
#include <utility>

#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/io/sequence.h"
#include "fluidtex/job/debug_views.h"
#include "fluidtex/job/frame_stats.h"
#include "fluidtex/job/frame_texturing.h"
#include "fluidtex/job/job_layout.h"
#include "fluidtex/job/job_record.h"
#include "fluidtex/tracking/patch_coverage.h"
#include "fluidtex/tracking/tracker.h"
#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/strings.h"
#include "fluidtex/util/timing.h"
#include "fluidtex/util/version.h"

namespace fluidtex {

namespace {

/// One frame in the pipeline: what reading, tracking and texturing leave for
/// the next stage. Tracking fills a snapshot (surface, patches or flow-map
/// uvs), so the frame's texturing does not depend on what runs beside it.
struct Work {
  std::size_t index = 0;
  int frame = 0;
  bool written = true;  // false: a frame a stepped range skips, followed but not textured (--skipped-frames)
  Clock::time_point started = Clock::now();
  std::shared_ptr<const FrameMesh> mesh;
  FrameStats stats;
  std::shared_ptr<const SurfaceIndex> surface;
  std::vector<Patch> patches;    // patches
  TrackingOptions resolved;      // patches
  double coverage_spacing = 0;   // patches
  FlowMapFrame flow;             // flowmap
  Tracker::UnpackedState state;  // patches: the tracker's state, packed in texture(), written last
  std::string packed_state;
};

/// A texturing method as the pipeline drives it: `track` runs serially in
/// frame order and fills the frame's snapshot (only for a written frame: a
/// followed one is tracked and nothing more), `texture` runs in parallel on
/// a snapshot, `finish` runs serially in frame order after the frame's
/// outputs are written.
class Texturing {
 public:
  virtual ~Texturing() = default;
  virtual void track(Work& work, double dt, bool first, Reporter& reporter) = 0;
  virtual void texture(Work& work) const = 0;
  virtual void finish(Work& work) const = 0;
  /// Disks that got no patch so far (logged once, in aggregate).
  virtual std::size_t failed() const { return 0; }
};

/// Gagnon et al. 2019: the tracker, then synthesis (or, with --track-only,
/// the coverage measure); the state file goes last.
class PatchTexturing final : public Texturing {
 public:
  /// `resumed_state`: the state file the tracker was loaded from (empty when fresh).
  PatchTexturing(Tracker tracker, const JobOptions& options, const TextureSource* source, std::string resumed_state)
      : tracker_(std::move(tracker)), options_(options), source_(source), write_state_(options.output.write_state),
        resumed_(!resumed_state.empty()), last_state_(std::move(resumed_state)) {}

  void track(Work& work, double dt, bool first, Reporter& reporter) override {
    StepReport step = tracker_.step(work.mesh, work.frame, dt);
    FrameStats& fs = work.stats;
    for (const auto& [stage, secs] : step.seconds) fs.seconds.emplace_back(stage, secs);
    const double area = tracker_.surface()->area();
    if (first) {
      const TrackingOptions& o = tracker_.settings().tracking;
      reporter.verbose("radius d " + std::to_string(o.d()) + ", thickness cs " + std::to_string(o.cs()) +
                       ", max projection mpt " + std::to_string(o.mpt()));
      if (!resumed_) {
        first_area_ = area;
        first_frame_ = work.frame;
      }
    }
    warn_of_growth(work.frame, area, reporter);
    if (!work.written) {
      add_counters(followed_, step);
      return;
    }
    // A written frame's counters (and state) cover every step since the
    // previous written frame.
    tracker_.prepend_retired(followed_.retired);
    add_counters(followed_, step);
    followed_.counts = step.counts;
    followed_.patch_vertices = step.patch_vertices;
    followed_.change.area = step.change.area;
    followed_.change.patches = step.change.patches;
    step = std::exchange(followed_, {});
    fs.patches = step.counts;
    fs.extra.emplace_back("patches_created", step.created);
    fs.extra.emplace_back("patches_refilled", step.refilled);
    fs.extra.emplace_back("patches_relaxed", step.relaxed);
    fs.extra.emplace_back("patches_recut", step.recut);
    for (auto& kv : recut_counts(step)) fs.extra.push_back(std::move(kv));
    fs.extra.emplace_back("patches_regrown", step.regrown);
    fs.extra.emplace_back("patches_removed", step.removed);
    fs.extra.emplace_back("patch_vertices", static_cast<double>(step.patch_vertices));
    for (auto& kv : retired_counts(step.retired)) fs.extra.push_back(std::move(kv));
    fs.extra.emplace_back("surface_area", area);
    if (step.change.measured())
      for (auto& kv : step.change.named()) fs.extra.push_back(std::move(kv));
    failed_ += static_cast<std::size_t>(step.failed);
    if (options_.output.debug_views) write_debug_views(work);
    work.surface = tracker_.shared_surface();
    work.patches = tracker_.patches();
    work.resolved = tracker_.settings().tracking;
    work.coverage_spacing = tracker_.coverage_spacing();
    if (write_state_) work.state = tracker_.unpacked_state();
  }

  void texture(Work& work) const override {
    if (write_state_) {
      const ScopedStage stage(work.stats.seconds, "state_pack");
      work.packed_state = Tracker::pack_state(work.state);
      work.state = {};
    }
    if (source_) {
      synthesize_frame(*work.surface, work.patches, work.resolved, *source_, options_, work.frame, work.stats);
      return;
    }
    // Track only: coverage measured on the surface (area with Σw = 0).
    const ScopedStage stage(work.stats.seconds, "coverage");
    const PatchCoverage coverage(work.patches, work.resolved.mpt());
    work.stats.uncovered_fraction = uncovered_area_fraction(*work.surface, coverage, work.coverage_spacing);
  }

  void finish(Work& work) const override {
    // The state goes last: its presence means the frame is complete (--resume).
    const ScopedStage stage(work.stats.seconds, "state");
    if (!write_state_) return;
    const std::string path = state_path(options_.output.dir, work.frame);
    write_text_atomically(path, work.packed_state);
    // --keep-state last: the previous state goes once the new one is in place.
    if (options_.output.keep_state == KeepState::Last && !last_state_.empty() && last_state_ != path) {
      std::error_code ignored;
      std::filesystem::remove(last_state_, ignored);
    }
    last_state_ = path;
  }

  std::size_t failed() const override { return failed_; }

 private:
  /// Adds the counters of `next` (the step after those summed in `sum`) to `sum`.
  static void add_counters(StepReport& sum, const StepReport& next) {
    sum.created += next.created;
    sum.refilled += next.refilled;
    sum.relaxed += next.relaxed;
    sum.recut += next.recut;
    sum.regrown += next.regrown;
    for (int c = 0; c < kRetireCauses; ++c) sum.recut_causes[c] += next.recut_causes[c];
    sum.removed += next.removed;
    sum.lost += next.lost;
    sum.failed += next.failed;
    sum.retired.insert(sum.retired.end(), next.retired.begin(), next.retired.end());
    for (int c = 0; c < kChangeClasses; ++c) {
      sum.change.births[c] += next.change.births[c];
      sum.change.removals[c] += next.change.removals[c];
    }
    sum.change.made += next.change.made;
    sum.change.lost += next.change.lost;
  }

  /// The automatic radius comes from the first frame's size. Liquid that
  /// starts small (an inflow, a tap) then gets patches for its first size:
  /// their number grows with the surface. Said once, when the surface has
  /// grown kGrowthWarning times, with what to do about it. `area`: the
  /// surface's at `frame`.
  void warn_of_growth(int frame, double area, Reporter& reporter) {
    static constexpr double kGrowthWarning = 10.0;
    if (growth_warned_ || options_.tracking.radius || !(first_area_ > 0.0)) return;
    const double growth = area / first_area_;
    if (!(growth >= kGrowthWarning)) return;
    growth_warned_ = true;
    char text[64];
    std::snprintf(text, sizeof text, "%.1f", growth);
    reporter.warn("frame " + std::to_string(frame) + ": the liquid's surface is " + text + " times frame " +
                  std::to_string(first_frame_) + "'s, whose size set the patch radius (--radius auto: d = " +
                  format_number(tracker_.settings().tracking.d()) +
                  "), so the patches multiply with it: for liquid that starts small, give --radius");
  }

  void write_debug_views(Work& work) const {
    const ScopedStage stage(work.stats.seconds, "debug");
    const std::vector<std::string> views = debug_view_patterns(options_.output.dir);
    write_patch_view(FramePattern(views[0]).path(work.frame), tracker_.patches());
    write_disk_view(FramePattern(views[1]).path(work.frame), tracker_.patches(), work.frame);
  }

  Tracker tracker_;
  const JobOptions& options_;
  const TextureSource* source_;  // null: track only
  bool write_state_;
  bool resumed_;                    // the tracker comes from a state: its radius from an earlier run's first frame
  mutable std::string last_state_;  // finish() runs serially, in frame order
  std::size_t failed_ = 0;
  StepReport followed_;      // the counters of the steps into frames followed since the last written one
  double first_area_ = 0.0;  // of the first frame's surface (0 when resumed)
  int first_frame_ = 0;
  bool growth_warned_ = false;
};

/// The two-phase advected-uv baseline: its "track" stage carries the two uv
/// sets to the frame; it keeps no state.
class FlowMapTexturing final : public Texturing {
 public:
  FlowMapTexturing(const JobOptions& options, const TextureSource& source)
      : advector_(settings(options)), options_(options), source_(source) {}

  void track(Work& work, double dt, bool first, Reporter& reporter) override {
    const FlowMapStep step = advector_.step(work.mesh, dt);
    for (const auto& [stage, secs] : step.seconds) work.stats.seconds.emplace_back(stage, secs);
    if (!work.written) return;
    const std::array<double, 2> w = phase_weights(step.step, options_.flowmap.period);
    work.stats.extra.emplace_back("weight_a", w[0]);
    work.stats.extra.emplace_back("weight_b", w[1]);
    if (first) {
      reporter.verbose("flowmap: tile size " + std::to_string(advector_.tile_size()) + ", period " +
                       std::to_string(options_.flowmap.period) + ", axis " + to_string(options_.flowmap.axis));
    }
    work.surface = advector_.shared_surface();
    work.flow = advector_.frame();
  }

  void texture(Work& work) const override {
    synthesize_flowmap_frame(*work.surface, work.flow, source_, options_, work.frame, work.stats,
                             advector_.tile_size());
  }

  void finish(Work&) const override {}

 private:
  static FlowMapSettings settings(const JobOptions& options) {
    FlowMapSettings fm;
    fm.flowmap = options.flowmap;
    fm.tracking = options.tracking;
    fm.exemplar_size = options.synthesis.exemplar_size;
    fm.seed = options.seed;
    return fm;
  }

  FlowMapAdvector advector_;
  const JobOptions& options_;
  const TextureSource& source_;
};

/// The patch method's tracker: from the newest state in OUT with --resume
/// (its index in `sequence` + 1 in `first`, its frame in `summary`), else
/// fresh. `written[i]`: frame i of `sequence` is written (has a state).
Tracker start_tracker(const JobOptions& options, const Sequence& sequence, const std::vector<char>& written,
                      Reporter& reporter, std::size_t& first, JobSummary& summary, std::string& resumed_state) {
  if (options.output.resume) {
    // The first written frame that is not complete (its outputs, or with
    // --track-only its state, missing: a frame deleted or lost after the
    // fact) bounds the resume: the job goes on from the newest state before
    // it and makes every frame after it again, as the uninterrupted run did.
    std::size_t limit = sequence.size();
    const std::vector<std::string> patterns = frame_output_patterns(options);
    for (std::size_t i = 0; i < sequence.size() && limit == sequence.size(); ++i) {
      if (!written[i]) continue;
      const int frame = sequence.frames()[i];
      const bool textured = std::all_of(patterns.begin(), patterns.end(), [&](const std::string& p) {
        return std::filesystem::exists(FramePattern(p).first_file(frame));
      });
      // A tracking step's frame is complete with its state, or textured by
      // synth (which may have pruned the state).
      const bool complete =
          textured || (options.synthesis.track_only && std::filesystem::exists(state_path(options.output.dir, frame)));
      if (!complete) limit = i;
    }
    if (limit < sequence.size() && !FramePattern(state_pattern(options.output.dir)).discover().empty())
      reporter.info("frame " + std::to_string(sequence.frames()[limit]) +
                    " of the job is incomplete: it and every frame after it are made again");
    // The newest state before it whose frame is in the sequence: every
    // output of that frame was written before it (the state is written last).
    for (std::size_t i = limit; i-- > 0;) {
      if (!written[i]) continue;
      const std::string path = state_path(options.output.dir, sequence.frames()[i]);
      if (!std::filesystem::exists(path)) continue;
      auto mesh = std::make_shared<const FrameMesh>(sequence.load(i));
      Tracker tracker = Tracker::load(path, std::move(mesh), sequence.frames()[i]);
      check_state_settings(tracker.settings(), options, path);
      first = i + 1;
      summary.resumed_after = sequence.frames()[i];
      reporter.info("resuming after frame " + std::to_string(summary.resumed_after) + " (" + path + ")");
      resumed_state = path;
      return tracker;
    }
    reporter.info("nothing to resume in " + options.output.dir + ": starting from the first frame");
  }
  TrackerSettings settings;
  settings.tracking = options.tracking;
  settings.advection = options.advection;
  settings.motion = options.patch_motion;
  settings.seed = options.seed;
  settings.coverage_aware = !options.no_coverage_check;
  return Tracker(settings);
}

/// Reads frame `index` of the sequence (cleaned) into a new Work.
std::shared_ptr<Work> read_frame(const Sequence& sequence, std::size_t index, bool written, const JobOptions& options,
                                 Reporter& reporter) {
  auto work = std::make_shared<Work>();
  work->index = index;
  work->frame = sequence.frames()[index];
  work->written = written;
  work->stats.method = to_string(options.method);
  try {
    work->mesh = read_frame_mesh(sequence, index, work->stats, reporter);
  } catch (const InputError& e) {
    if (written) throw;
    throw InputError(e.file(), e.problem() +
                                   " (a frame the stepped range skips, read to carry the texture through it; "
                                   "--skipped-frames ignore steps across it)");
  }
  return work;
}

}  // namespace

namespace {

/// Adds `secs` to `stage`'s entry of `seconds` (appended when it has none).
void add_seconds(StageSeconds& seconds, const std::string& stage, double secs) {
  const auto at = std::find_if(seconds.begin(), seconds.end(), [&](const auto& kv) { return kv.first == stage; });
  if (at == seconds.end()) {
    seconds.emplace_back(stage, secs);
  } else {
    at->second += secs;
  }
}

/// The job record this run writes, once the output folder is its own: with
/// --resume the job in OUT must be this one (check_resumable); without, OUT
/// must hold no other job's outputs unless --force (claim_output_folder).
JobRecord claim_job(const JobOptions& options, const Sequence& sequence, Reporter& reporter) {
  JobRecord record = make_job_record(options, sequence.frames());
  const std::string path = job_record_path(options.output.dir);
  if (!options.output.resume) {
    const std::size_t removed = claim_output_folder(options);
    if (removed > 0) reporter.info("--force: removed " + std::to_string(removed) + " files of the earlier job");
  } else if (std::filesystem::exists(path)) {
    const JobRecord job = read_job_record(options.output.dir);
    check_resumable(job, record);
    if (job.frames.size() > record.frames.size()) record.frames = job.frames;  // a shorter resume keeps them
  } else if (!FramePattern(state_pattern(options.output.dir)).discover().empty()) {
    throw InputError(path, "missing: the states in " + options.output.dir +
                               "/state cannot be checked against a job (--force replaces them)");
  }
  return record;
}

/// Says where the frame rate comes from, and warns when --fps contradicts
/// the rate the input's header states.
void report_frame_rate(const Sequence& sequence, Reporter& reporter) {
  const std::string first = sequence.path_of(sequence.frames().front());
  const std::optional<double> stated = sequence.stated_fps();
  const std::string fps = format_number(sequence.fps());
  const FpsSource source = sequence.fps_source();
  if (source == FpsSource::Given && stated && std::abs(*stated - sequence.fps()) > 1e-6 * *stated) {
    reporter.warn("--fps " + fps + " given, but " + first + " states " + format_number(*stated) +
                  " fps in its header: the frame step is 1/" + fps + " s, as given");
  } else if (source == FpsSource::Header) {
    reporter.info(fps + " fps, as " + first + " states in its header");
  } else if (source == FpsSource::Default) {
    reporter.info(fps + " fps (the default: " + first + " states no frame rate; --fps sets it)");
  }
}

/// Says what one exemplar tile spans on the surface (exemplar_span) and
/// returns it: from --exemplar-size, else (2 + β)·d over s, d from --radius
/// or, as the tracker and the flow map resolve it, from the first frame's
/// size (read here once more).
double report_exemplar_span(const JobOptions& options, const Sequence& sequence, Reporter& reporter) {
  const bool from_first_frame = !options.synthesis.exemplar_size && !options.tracking.radius;
  const TrackingOptions resolved =
      options.tracking.resolved(from_first_frame ? bounding_box(sequence.load(0)).diagonal() : 0.0);
  const double span = exemplar_span(resolved, options.synthesis);
  char text[160];
  if (options.synthesis.exemplar_size) {
    std::snprintf(text, sizeof text, "one exemplar tile spans %.4g scene units on the surface (--exemplar-size)", span);
  } else {
    std::snprintf(text, sizeof text,
                  "one exemplar tile spans %.4g scene units on the surface (auto: %.3g x radius %.4g%s; "
                  "--exemplar-size sets it)",
                  span, resolved.exemplar_tile_size() / (resolved.d() * resolved.uv_scale), resolved.d(),
                  from_first_frame ? ", from the first frame's size" : "");
  }
  reporter.info(text);
  return span;
}

/// Which frames of `sequence` (the frames stepped through) are written:
/// those of `written_frames`, not the ones a stepped range only follows.
std::vector<char> written_flags(const Sequence& sequence, const Sequence& written_frames) {
  std::vector<char> written(sequence.size());
  const std::vector<int>& frames = written_frames.frames();
  for (std::size_t i = 0; i < sequence.size(); ++i)
    written[i] = std::binary_search(frames.begin(), frames.end(), sequence.frames()[i]);
  return written;
}

/// The run's texturing method, its frames stamped with the job's settings
/// hash (`stamped`); for the patch method from the state --resume finds
/// (`first`: the index of the first frame to make, `summary.resumed_after`).
std::unique_ptr<Texturing> start_texturing(const JobOptions& options, const JobOptions& stamped,
                                           const Sequence& sequence, const std::vector<char>& written,
                                           const std::optional<TextureSource>& source, Reporter& reporter,
                                           std::size_t& first, JobSummary& summary) {
  if (options.method == TexturingMethod::FlowMap) return std::make_unique<FlowMapTexturing>(stamped, *source);
  std::string resumed_state;
  Tracker tracker = start_tracker(options, sequence, written, reporter, first, summary, resumed_state);
  return std::make_unique<PatchTexturing>(std::move(tracker), stamped, source ? &*source : nullptr,
                                          std::move(resumed_state));
}

/// A run's frames through the frame pipeline (run_frames): the time step
/// from the previous frame, the seconds of frames followed but not written
/// (added to the next written one), the stats lines, and which frames have
/// all their outputs, so that a failure leaves each frame complete or absent.
class RunFrames {
 public:
  RunFrames(const JobOptions& options, const Sequence& sequence, const std::vector<char>& written, Texturing& method,
            std::size_t first, JobSummary& summary, Reporter& reporter)
      : options_(options), sequence_(sequence), written_(written), method_(method), first_(first), next_(first),
        committed_(first), previous_frame_(summary.resumed_after), summary_(summary), reporter_(reporter),
        stats_(options.output.dir + "/stats.jsonl", summary.resumed_after >= 0) {}

  void run() {
    try {
      run_frames(FrameStages<Work>{.read = [this] { return read(); },
                                   .track = [this](Work& work) { track(work); },
                                   .texture = [this](Work& work) { texture(work); },
                                   .write = [this](Work& work) { write(work); }});
    } catch (...) {
      remove_uncommitted();
      throw;
    }
  }

 private:
  std::shared_ptr<Work> read() {
    if (next_ >= sequence_.size()) return nullptr;
    const std::size_t index = next_++;
    return read_frame(sequence_, index, written_[index], options_, reporter_);
  }

  void track(Work& work) {
    reporter_.progress(work.index, sequence_.size(), "track");
    const double dt = previous_frame_ == -1 ? 1.0 / sequence_.fps()
                                            : static_cast<double>(work.frame - previous_frame_) / sequence_.fps();
    method_.track(work, dt, work.index == first_, reporter_);
    previous_frame_ = work.frame;
    // A written frame's seconds include those of the frames followed since
    // the previous one (reading and tracking them).
    if (!work.written) {
      ++steps_followed_;
      for (const auto& [stage, secs] : work.stats.seconds) add_seconds(followed_seconds_, stage, secs);
    } else if (steps_followed_ > 0) {
      for (const auto& [stage, secs] : followed_seconds_) add_seconds(work.stats.seconds, stage, secs);
      work.stats.extra.emplace_back("frames_followed", steps_followed_);
      followed_seconds_.clear();
      steps_followed_ = 0;
    }
  }

  void texture(Work& work) const {
    if (work.written) method_.texture(work);
  }

  void write(Work& work) {
    if (work.written) method_.finish(work);
    committed_ = work.index + 1;
    if (!work.written) return;
    stats_.add(work.stats);
    ++summary_.frames;
    reporter_.frame_done(frame_report(options_.synthesis.track_only ? "track" : "run", work.stats, work.started,
                                      options_.method == TexturingMethod::Patches));
    reporter_.progress(work.index + 1, sequence_.size(), "written");
  }

  /// Frames in flight may have their atlas and mesh on disk already: a frame
  /// is complete with its state, or absent (--resume makes it again).
  void remove_uncommitted() const {
    if (options_.method != TexturingMethod::Patches || !options_.output.write_state) return;
    for (std::size_t i = committed_; i < sequence_.size(); ++i) {
      if (written_[i]) remove_frame_outputs(options_, sequence_.frames()[i]);
    }
  }

  const JobOptions& options_;
  const Sequence& sequence_;
  const std::vector<char>& written_;
  Texturing& method_;
  std::size_t first_;
  std::size_t next_;
  std::size_t committed_;  // frames [first, committed) have all their outputs
  int previous_frame_;
  StageSeconds followed_seconds_;  // of the frames followed since the last written one
  int steps_followed_ = 0;
  JobSummary& summary_;
  Reporter& reporter_;
  StatsWriter stats_;
};

}  // namespace

JobSummary run_job(const JobOptions& requested, Reporter& reporter) {
  const auto start = Clock::now();
  requested.validate();
  check_output_paths(requested);
  // A run owns its whole folder: other machines' temporaries go too.
  if (const std::size_t stale = remove_interrupted_temporaries(requested, [](const std::string&) { return true; }))
    reporter.verbose("removed " + std::to_string(stale) + " temporary files of an interrupted run");
  const Sequence written_frames(requested.input);
  report_frame_rate(written_frames, reporter);
  JobOptions options = requested;  // with the frame rate job.toml records, eval and synth read
  options.input.fps = written_frames.fps();
  // The frames stepped through: the written ones and, with --skipped-frames
  // follow, the frames on disk that a stepped range skips.
  const Sequence sequence = written_frames.followed();
  if (sequence.size() > written_frames.size()) {
    reporter.info("following " + std::to_string(sequence.size() - written_frames.size()) +
                  " frames on disk between the " + std::to_string(written_frames.size()) +
                  " written (--skipped-frames follow)");
  }
  const std::vector<char> written = written_flags(sequence, written_frames);
  std::optional<TextureSource> source;  // read once, before any output (fails early when unreadable)
  if (!options.synthesis.track_only) {
    std::string warning;
    source.emplace(load_texture_source(options, &warning));
    if (!warning.empty()) reporter.warn(warning);
  }
  JobRecord record = claim_job(options, written_frames, reporter);
  if (source) record.exemplar_size = report_exemplar_span(options, sequence, reporter);
  JobOptions stamped = options;  // what the frames are written with
  stamped.output.provenance = settings_hash(record);
  std::size_t first = 0;
  JobSummary summary;
  const std::unique_ptr<Texturing> method =
      start_texturing(options, stamped, sequence, written, source, reporter, first, summary);
  RunFrames frames(options, sequence, written, *method, first, summary, reporter);
  write_text_atomically(job_record_path(options.output.dir), job_record_toml(record));
  try {
    frames.run();
  } catch (...) {
    // A new job that made no frame leaves no record either: the folder is
    // as the run found it (emptied by --force), and the corrected command
    // runs without --force.
    if (summary.frames == 0 && !options.output.resume) {
      std::error_code ignored;
      std::filesystem::remove(job_record_path(options.output.dir), ignored);
      std::filesystem::remove(options.output.dir + "/stats.jsonl", ignored);
    }
    throw;
  }
  if (method->failed() > 0) {
    reporter.warn(std::to_string(method->failed()) +
                  " new disks got no patch (degenerate selection or failed LSCM solve)");
  }
  reporter.progress(sequence.size(), sequence.size(), "done");
  summary.seconds = seconds_since(start);
  return summary;
}

}  // namespace fluidtex
