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

#include <oneapi/tbb/parallel_pipeline.h>

#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/io/image_io.h"
#include "fluidtex/io/sequence.h"
#include "fluidtex/io/stats.h"
#include "fluidtex/io/uv_mesh_io.h"
#include "fluidtex/job/debug_views.h"
#include "fluidtex/job/frame_layers.h"
#include "fluidtex/job/job_layout.h"
#include "fluidtex/job/job_record.h"
#include "fluidtex/tracking/patch_locator.h"
#include "fluidtex/tracking/tracker.h"
#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/strings.h"
#include "fluidtex/util/timing.h"
#include "fluidtex/util/version.h"

namespace fluidtex {

Exemplar load_exemplar(const std::string& path, bool displacement) {
  Image image = read_image(path);
  if (displacement && image.channels >= 3) {
    Image grey;
    grey.width = image.width, grey.height = image.height, grey.channels = 1;
    grey.pixels.resize(static_cast<std::size_t>(image.width) * image.height);
    for (std::size_t i = 0; i < grey.pixels.size(); ++i) {
      const float* p = &image.pixels[i * image.channels];
      grey.pixels[i] = rec709_luminance(p[0], p[1], p[2]);
    }
    image = std::move(grey);
  } else if (displacement && image.channels == 2) {
    image.channels = 1;  // grey + alpha: keep grey
    for (std::size_t i = 0; i < static_cast<std::size_t>(image.width) * image.height; ++i)
      image.pixels[i] = image.pixels[2 * i];
    image.pixels.resize(static_cast<std::size_t>(image.width) * image.height);
  }
  if (image.channels == 2) throw InputError(path, "exemplar has 2 channels (expected grey, RGB or RGBA)");
  for (float v : image.pixels) {
    if (!std::isfinite(v)) throw InputError(path, "exemplar has NaN or infinite pixels");
  }
  return Exemplar(std::move(image));
}

SynthesisOptions synthesis_options(const TrackingOptions& resolved, const SynthesisJobOptions& so) {
  SynthesisOptions synth;
  synth.blend = so.blend;
  synth.method = so.method;
  synth.weight_cutoff = so.weight_cutoff;
  synth.uv_scale = resolved.uv_scale;
  synth.radius = resolved.d();
  // One exemplar tile spans (2 + β)·d at s = 1: a patch's disk shows most of
  // a tile, each patch a different part of it (its random anchor).
  synth.tile_size = resolved.exemplar_tile_size();
  synth.projection_tolerance = resolved.mpt();  // as the tracker's coverage test
  synth.aov = !so.aov.empty();
  return synth;
}

namespace {

/// The frame's layers (kFrameLayers) that the job writes, each with its
/// pixel encoding; returns the material's maps for the OBJ.
MaterialMaps write_frame_layers(const JobOptions& options, int frame, const FrameSynthesis& textured,
                                const ImageWriteOptions& color_write) {
  MaterialMaps maps(std::filesystem::absolute(FramePattern(options.output.atlas()).path(frame)).string());
  for (std::size_t i = 0; i < kFrameLayerCount; ++i) {
    const std::string pattern = options.layer_pattern(i);
    if (pattern.empty()) continue;
    const FrameLayer& layer = kFrameLayers[i];
    const std::string path = std::filesystem::absolute(FramePattern(pattern).path(frame)).string();
    write_image(path, layer.make(textured), layer_write_options(layer, color_write));
    if (layer.slot == MaterialSlot::Height) {
      maps.displacement = path;
      maps.bump_height = textured.bump_height;
    } else if (layer.slot == MaterialSlot::Normal) {
      maps.normal = path;
    }
  }
  return maps;
}

/// A frame's atlas, texel map, texels (`texels(atlas, map)`, either method)
/// and writes, with the synthesis numbers and stage seconds in `stats`.
/// `tile_size`: the exemplar's size on the surface (--bump-height's unit).
template <class Texels>
void atlas_frame(const SurfaceIndex& surface, const JobOptions& options, int frame, FrameStats& stats, double tile_size,
                 Texels&& texels) {
  const SynthesisJobOptions& so = options.synthesis;
  auto t0 = Clock::now();
  const Atlas atlas = build_atlas(surface, so.atlas);
  stats.seconds.emplace_back("atlas", seconds_since(t0));
  t0 = Clock::now();
  const TexelMap map = build_texel_map(surface, atlas);
  const SynthesisResult result = texels(atlas, map);
  const double synth_seconds = seconds_since(t0);
  stats.seconds.emplace_back("synthesis", synth_seconds);

  // A texel that is not finite is a bug, never an output (options bound the
  // scales that could overflow).
  for (float v : result.color.pixels) {
    if (!std::isfinite(v)) throw InternalError("frame " + std::to_string(frame) + ": the atlas has non-finite texels");
  }

  t0 = Clock::now();
  ImageWriteOptions write;
  write.depth = so.float_output ? PixelDepth::Float : PixelDepth::Default;
  write.compression = so.compression;
  write.dwa_level = so.dwa_level;
  write.layout = so.layout;
  write.metadata = {{"fluidtex:version", version_line()},
                    {"fluidtex:frame", std::to_string(frame)},
                    {"fluidtex:settings", options.output.provenance}};
  write_image(FramePattern(options.output.atlas()).path(frame), result.color, write);
  // An OBJ names its atlas through a material (<stem>.mtl, map_Kd; disp,
  // bump and norm for the height and normal atlases), so a DCC imports it
  // textured.
  const MaterialMaps maps =
      write_frame_layers(options, frame, FrameSynthesis{atlas, map, result, so.bump_height * tile_size}, write);
  write_uv_mesh(FramePattern(options.output.mesh()).path(frame), atlas_uv_mesh(surface, atlas), maps);
  stats.seconds.emplace_back("write", seconds_since(t0));

  stats.uncovered_fraction = result.uncovered_fraction();
  stats.extra.emplace_back("packing_efficiency", atlas.packing_efficiency);
  stats.extra.emplace_back("charts", static_cast<double>(atlas.charts.size()));
  stats.extra.emplace_back("chart_texels", static_cast<double>(result.chart_texels));
  stats.extra.emplace_back("margin_texels", static_cast<double>(result.margin_texels));
  stats.extra.emplace_back("binned_triangles", static_cast<double>(result.binned_triangles));
  stats.extra.emplace_back("projected_triangles", static_cast<double>(result.projected_triangles));
  stats.extra.emplace_back(
      "clamped_fraction", result.chart_texels ? static_cast<double>(result.clamped_texels) / result.chart_texels : 0.0);
  stats.extra.emplace_back("texels_per_second", synth_seconds > 0 ? result.chart_texels / synth_seconds : 0.0);
}

}  // namespace

void synthesize_frame(const SurfaceIndex& surface, const std::vector<Patch>& patches, const TrackingOptions& resolved,
                      const Exemplar& exemplar, const JobOptions& options, int frame, FrameStats& stats) {
  atlas_frame(
      surface, options, frame, stats, resolved.exemplar_tile_size(), [&](const Atlas& atlas, const TexelMap& map) {
        return synthesize(surface, atlas, map, patches, exemplar, synthesis_options(resolved, options.synthesis));
      });
}

void synthesize_flowmap_frame(const SurfaceIndex& surface, const FlowMapFrame& flow, const Exemplar& exemplar,
                              const JobOptions& options, int frame, FrameStats& stats, double tile_size) {
  atlas_frame(surface, options, frame, stats, tile_size, [&](const Atlas& atlas, const TexelMap& map) {
    return synthesize_flowmap(surface, atlas, map, flow, exemplar, options.synthesis.blend,
                              !options.synthesis.aov.empty());
  });
}

FrameReport frame_report(const char* step, const FrameStats& stats, Clock::time_point started, bool has_patches) {
  FrameReport done;
  done.step = step;
  done.frame = stats.frame;
  done.seconds = seconds_since(started);
  if (has_patches) done.patches = stats.patches.total();
  return done;
}

std::shared_ptr<const FrameMesh> read_frame_mesh(const Sequence& sequence, std::size_t index, FrameStats& stats,
                                                 Reporter& reporter) {
  stats.frame = sequence.frames()[index];
  const ScopedStage stage(stats.seconds, "read");
  CleanReport cleaned;
  auto mesh = std::make_shared<const FrameMesh>(sequence.load(index, &cleaned));
  if (cleaned.changed()) reporter.verbose(sequence.path_of(stats.frame) + ": " + cleaned.summary());
  stats.vertices = mesh->num_vertices();
  stats.faces = mesh->num_faces();
  return mesh;
}

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
  PatchTexturing(Tracker tracker, const JobOptions& options, const Exemplar* exemplar, std::string resumed_state)
      : tracker_(std::move(tracker)), options_(options), exemplar_(exemplar), write_state_(options.output.write_state),
        resumed_(!resumed_state.empty()), last_state_(std::move(resumed_state)) {}

  void track(Work& work, double dt, bool first, Reporter& reporter) override {
    StepReport step = tracker_.step(work.mesh, work.frame, dt);
    FrameStats& fs = work.stats;
    for (const auto& [stage, secs] : step.seconds) fs.seconds.emplace_back(stage, secs);
    const double area = tracker_.surface()->area();
    if (first) {
      const TrackingOptions& o = tracker_.settings().method;
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
    work.resolved = tracker_.settings().method;
    work.coverage_spacing = tracker_.coverage_spacing();
    if (write_state_) work.state = tracker_.unpacked_state();
  }

  void texture(Work& work) const override {
    if (write_state_) {
      const ScopedStage stage(work.stats.seconds, "state_pack");
      work.packed_state = Tracker::pack_state(work.state);
      work.state = {};
    }
    if (exemplar_) {
      synthesize_frame(*work.surface, work.patches, work.resolved, *exemplar_, options_, work.frame, work.stats);
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
                  option_detail::format_number(tracker_.settings().method.d()) +
                  "), so the patches multiply with it: for liquid that starts small, give --radius");
  }

  void write_debug_views(Work& work) const {
    const ScopedStage stage(work.stats.seconds, "debug");
    const std::string dir = options_.output.dir + "/debug";
    write_patch_view(FramePattern(dir + "/patches.####.ply").path(work.frame), tracker_.patches());
    write_disk_view(FramePattern(dir + "/disks.####.ply").path(work.frame), tracker_.patches(), work.frame);
  }

  Tracker tracker_;
  const JobOptions& options_;
  const Exemplar* exemplar_;
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
  FlowMapTexturing(const JobOptions& options, const Exemplar& exemplar)
      : advector_(settings(options)), options_(options), exemplar_(exemplar) {}

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
    synthesize_flowmap_frame(*work.surface, work.flow, exemplar_, options_, work.frame, work.stats,
                             advector_.tile_size());
  }

  void finish(Work&) const override {}

 private:
  static FlowMapSettings settings(const JobOptions& options) {
    FlowMapSettings fm;
    fm.flowmap = options.flowmap;
    fm.method = options.tracking;
    fm.seed = options.seed;
    return fm;
  }

  FlowMapAdvector advector_;
  const JobOptions& options_;
  const Exemplar& exemplar_;
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
        return std::filesystem::exists(FramePattern(p).path(frame));
      });
      // A tracking step's frame is complete with its state, or textured by
      // synth (which may have pruned the state).
      const bool complete =
          textured || (options.synthesis.track_only && std::filesystem::exists(state_path(options.output.dir, frame)));
      if (!complete) limit = i;
    }
    if (limit < sequence.size() && FramePattern(state_pattern(options.output.dir)).discover().size() > 0)
      reporter.info("frame " + std::to_string(sequence.frames()[limit]) +
                    " of the job is incomplete: it and every frame after it are made again");
    // The newest state before it whose frame is in the sequence: every
    // output of that frame was written before it (the state is written last).
    for (std::size_t i = limit; i-- > 0;) {
      if (!written[i]) continue;
      const std::string path = state_path(options.output.dir, sequence.frames()[i]);
      if (!std::filesystem::exists(path)) continue;
      auto mesh = std::make_shared<const FrameMesh>(sequence.load(i));
      Tracker tracker = Tracker::load(path, std::move(mesh));
      first = i + 1;
      summary.resumed_after = sequence.frames()[i];
      reporter.info("resuming after frame " + std::to_string(summary.resumed_after) + " (" + path + ")");
      resumed_state = path;
      return tracker;
    }
    reporter.info("nothing to resume in " + options.output.dir + ": starting from the first frame");
  }
  TrackerSettings settings;
  settings.method = options.tracking;
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
  const std::string fps = option_detail::format_number(sequence.fps());
  const FpsSource source = sequence.fps_source();
  if (source == FpsSource::Given && stated && std::abs(*stated - sequence.fps()) > 1e-6 * *stated) {
    reporter.warn("--fps " + fps + " given, but " + first + " states " + option_detail::format_number(*stated) +
                  " fps in its header: the frame step is 1/" + fps + " s, as given");
  } else if (source == FpsSource::Header) {
    reporter.info(fps + " fps, as " + first + " states in its header");
  } else if (source == FpsSource::Default) {
    reporter.info(fps + " fps (the default: " + first + " states no frame rate; --fps sets it)");
  }
}

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
  std::vector<char> written(sequence.size());
  for (std::size_t i = 0; i < sequence.size(); ++i) {
    written[i] =
        std::binary_search(written_frames.frames().begin(), written_frames.frames().end(), sequence.frames()[i]);
  }
  std::optional<Exemplar> exemplar;  // read once, before any output (fails early when unreadable)
  if (!options.synthesis.track_only) exemplar.emplace(load_exemplar(options.exemplar, options.synthesis.displacement));
  const JobRecord record = claim_job(options, written_frames, reporter);
  JobOptions stamped = options;  // what the frames are written with
  stamped.output.provenance = settings_hash(record);
  std::size_t first = 0;
  JobSummary summary;
  std::unique_ptr<Texturing> method;
  if (options.method == TexturingMethod::FlowMap) {
    method = std::make_unique<FlowMapTexturing>(stamped, *exemplar);
  } else {
    std::string resumed_state;
    Tracker tracker = start_tracker(options, sequence, written, reporter, first, summary, resumed_state);
    method = std::make_unique<PatchTexturing>(std::move(tracker), stamped, exemplar ? &*exemplar : nullptr,
                                              std::move(resumed_state));
  }

  StatsWriter stats(options.output.dir + "/stats.jsonl", summary.resumed_after >= 0);
  write_text_atomically(job_record_path(options.output.dir), job_record_toml(record));
  int previous_frame = summary.resumed_after;
  StageSeconds followed_seconds;  // of the frames followed since the last written one
  int steps_followed = 0;

  // Frames flow through a TBB pipeline: read → track → texture → write.
  // Reading frame t+1, tracking and texturing overlap; tracking and the final
  // writes stay in frame order. At most `tokens` frames are in flight, so
  // memory does not grow with the sequence.
  std::size_t next = first;
  const std::size_t tokens = 3;
  using WorkPtr = std::shared_ptr<Work>;
  auto read = [&](tbb::flow_control& fc) -> WorkPtr {
    if (next < sequence.size()) {
      const std::size_t index = next++;
      return read_frame(sequence, index, written[index], options, reporter);
    }
    fc.stop();
    return nullptr;
  };
  auto track = [&](WorkPtr work) {
    reporter.progress(work->index, sequence.size(), "track");
    const double dt = previous_frame == -1 ? 1.0 / sequence.fps()
                                           : static_cast<double>(work->frame - previous_frame) / sequence.fps();
    isolated_stage([&] { method->track(*work, dt, work->index == first, reporter); });
    previous_frame = work->frame;
    // A written frame's seconds include those of the frames followed since
    // the previous one (reading and tracking them).
    if (!work->written) {
      ++steps_followed;
      for (const auto& [stage, secs] : work->stats.seconds) add_seconds(followed_seconds, stage, secs);
    } else if (steps_followed > 0) {
      for (const auto& [stage, secs] : followed_seconds) add_seconds(work->stats.seconds, stage, secs);
      work->stats.extra.emplace_back("frames_followed", steps_followed);
      followed_seconds.clear();
      steps_followed = 0;
    }
    return work;
  };
  auto texture = [&](WorkPtr work) {
    if (work->written) isolated_stage([&] { method->texture(*work); });
    return work;
  };
  std::size_t committed = first;  // frames [first, committed) have all their outputs
  auto write = [&](const WorkPtr& work) {
    if (!work->written) {
      committed = work->index + 1;
      return;
    }
    method->finish(*work);
    committed = work->index + 1;
    stats.add(work->stats);
    ++summary.frames;
    reporter.frame_done(frame_report(options.synthesis.track_only ? "track" : "run", work->stats, work->started,
                                     options.method == TexturingMethod::Patches));
    reporter.progress(work->index + 1, sequence.size(), "written");
  };
  try {
    tbb::parallel_pipeline(tokens, tbb::make_filter<void, WorkPtr>(tbb::filter_mode::serial_in_order, read) &
                                       tbb::make_filter<WorkPtr, WorkPtr>(tbb::filter_mode::serial_in_order, track) &
                                       tbb::make_filter<WorkPtr, WorkPtr>(tbb::filter_mode::parallel, texture) &
                                       tbb::make_filter<WorkPtr, void>(tbb::filter_mode::serial_in_order, write));
  } catch (...) {
    // Frames in flight may have their atlas and mesh on disk already: a
    // frame is complete with its state, or absent (--resume redoes it).
    if (options.method == TexturingMethod::Patches && options.output.write_state) {
      for (std::size_t i = committed; i < sequence.size(); ++i) {
        if (written[i]) remove_frame_outputs(options, sequence.frames()[i]);
      }
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
