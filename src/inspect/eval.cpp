#include "fluidtex/inspect/eval.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <numeric>
#include <optional>

#include "fluidtex/geometry/distortion.h"
#include "fluidtex/geometry/surface.h"
#include "fluidtex/inspect/appearance_metrics.h"
#include "fluidtex/inspect/eval_report.h"
#include "fluidtex/inspect/motion_metrics.h"
#include "fluidtex/inspect/patch_history.h"
#include "fluidtex/inspect/texture_metrics.h"
#include "fluidtex/inspect/textured_frame.h"
#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/io/image_io.h"
#include "fluidtex/io/sequence.h"
#include "fluidtex/job/frame_texturing.h"
#include "fluidtex/job/job_layout.h"
#include "fluidtex/texture/synthesis.h"
#include "fluidtex/tracking/patch_coverage.h"
#include "fluidtex/tracking/tracker.h"
#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/json.h"

namespace fluidtex {

namespace {

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

/// The report shows the worst frame of at most this many bad frame ranges.
constexpr int kWorstImages = 6;

/// Coverage (surface area and texels with Σw = 0), ghosting (patches blended
/// per texel, re-synthesised with the count layer) and distortion of the
/// frame's patches.
void patch_figures(const Tracker& tracker, const JobOptions& job, const Exemplar& exemplar, MetricRow& row) {
  const TrackingOptions& o = tracker.settings().tracking;
  const std::vector<Patch>& patches = tracker.patches();
  const PatchCoverage coverage(patches, o.mpt());
  row.emplace_back("uncovered_area", uncovered_area_fraction(*tracker.surface(), coverage, tracker.coverage_spacing()));
  SynthesisOptions so = synthesis_options(o, job.synthesis);
  so.aov = true;
  const Atlas atlas = build_atlas(*tracker.surface(), job_atlas_options(job));
  std::vector<double> count;
  std::size_t chart_texels = 0, uncovered_texels = 0;
  for (int tile = 0; tile < atlas.tiles; ++tile) {
    const TexelMap map = build_texel_map(*tracker.surface(), atlas, tile);
    const SynthesisResult synth = synthesize(*tracker.surface(), atlas, map, patches, exemplar, so);
    chart_texels += synth.chart_texels;
    uncovered_texels += synth.uncovered_texels;
    for (std::size_t t = 0; t < map.face.size(); ++t) {
      if (map.face[t] >= 0) count.push_back(synth.count.pixels[t]);
    }
  }
  row.emplace_back("uncovered_texels",
                   chart_texels ? static_cast<double>(uncovered_texels) / static_cast<double>(chart_texels) : 0.0);
  row.emplace_back("ghosting_mean",
                   count.empty() ? std::nan("") : std::accumulate(count.begin(), count.end(), 0.0) / count.size());
  row.emplace_back("ghosting_p95", quantile(count, 0.95));

  std::vector<double> distortion;
  std::size_t vertices = 0, poor = 0;
  for (const Patch& p : patches) {
    for (std::size_t t = 0; t < p.triangles.size(); ++t) {
      const Tri& tri = p.triangles[t];
      distortion.push_back(
          triangle_distortion(p.rest[t], p.positions[tri[0]], p.positions[tri[1]], p.positions[tri[2]]));
    }
    for (float q : p.quality) vertices++, poor += q < 0.5f;
  }
  row.emplace_back("distortion_median", quantile(distortion, 0.5));
  row.emplace_back("distortion_p95", quantile(distortion, 0.95));
  row.emplace_back("distortion_max",
                   distortion.empty() ? std::nan("") : *std::max_element(distortion.begin(), distortion.end()));
  row.emplace_back("quality_below_half", vertices ? static_cast<double>(poor) / vertices : std::nan(""));
}

/// Exemplar texels per atlas texel where the exemplar lands on the surface
/// (its tile's span at the atlas's texel density `density`).
double exemplar_scale(const TrackingOptions& resolved, const SynthesisJobOptions& so, const Exemplar& exemplar,
                      double density) {
  return exemplar.image().width * resolved.uv_scale / (resolved.exemplar_tile_size(so.exemplar_size) * density);
}

/// The radial spectrum distance of the mean log spectrum of up to 64 atlas
/// windows inside the charts (64², or 32² or 16² where none fits) to that of
/// 32 exemplar crops at `scale`.
void spectrum_figures(const Image& atlas, const std::vector<char>& mask, const Exemplar& exemplar, double scale,
                      MetricRow& row) {
  double spectrum = std::nan("");
  for (int n : {64, 32, 16}) {
    // 64 windows a frame and 32 exemplar crops: with 8 of each a frame's
    // figure depends on which 8 places of the surface the chart layout
    // puts first in scan order.
    const auto windows = chart_windows(mask, atlas.width, n, 64);
    if (windows.empty() || !(scale > 0.0)) continue;
    // The windows' mean log spectrum against the crops' (exemplar_spectrum):
    // one window's periodogram is too noisy to compare on its own (a tiled
    // exemplar's windows scored 0.36 each against the mean of its crops).
    const std::vector<double> reference = exemplar_spectrum(exemplar, scale, n, 32);
    std::vector<double> mean(reference.size(), 0.0);
    for (const auto& [x, y] : windows) {
      const std::vector<double> s = radial_log_spectrum(atlas, x, y, n);
      for (std::size_t b = 0; b < s.size(); ++b) mean[b] += s[b] / static_cast<double>(windows.size());
    }
    spectrum = spectrum_distance(mean, reference);
    row.emplace_back("spectrum_crop", n);
    break;
  }
  row.emplace_back("spectrum_distance", spectrum);
}

/// The plane eval reads directions on the surface in: the flow map's rest
/// projection (its u and v as world directions), where the flow map shows
/// the exemplar unturned.
DirectionFrame direction_frame(const FlowMapOptions& flowmap) {
  const Vec2 x = rest_uv(Vec3::UnitX(), flowmap.axis, 1.0), y = rest_uv(Vec3::UnitY(), flowmap.axis, 1.0),
             z = rest_uv(Vec3::UnitZ(), flowmap.axis, 1.0);
  return {Vec3(x.x(), y.x(), z.x()), Vec3(x.y(), y.y(), z.y())};
}

/// The centres of the frame's live disks (not fading out), scene units.
std::vector<Vec3> live_centres(const std::vector<Patch>& patches) {
  std::vector<Vec3> centres;
  for (const Patch& p : patches) {
    if (!is_fading_out(p.state)) centres.push_back(p.centre.point.position);
  }
  return centres;
}

/// Whether the patch layout shows (appearance_metrics.h): the
/// autocorrelation at `lag` atlas texels in 8 directions over the charts,
/// and, where the frame has live `centres`, the correlation around each
/// centre and its nearest neighbour (views half a lag wide: the part of
/// the surface each patch dominates), both against the exemplar's at
/// `scale`.
void patch_layout_figures(const TexturedFrame& frame, const std::vector<char>& mask, const Exemplar& exemplar,
                          double scale, double lag, double density, const std::vector<Vec3>& centres,
                          const DirectionFrame& directions, MetricRow& row) {
  const Image& atlas = frame.atlas.first();
  const LayoutFigures layout = layout_figures(atlas, mask, exemplar, scale, lag);
  row.emplace_back("layout_lag_px", layout.lag);
  row.emplace_back("layout_autocorrelation", layout.atlas);
  row.emplace_back("layout_autocorrelation_exemplar", layout.exemplar);
  row.emplace_back("layout_autocorrelation_excess", layout.excess);
  if (centres.empty() || !std::isfinite(lag)) return;
  const int n = std::max(8, static_cast<int>(std::lround(0.5 * lag)));
  const NeighbourFigures near =
      neighbour_figures(atlas, mask, exemplar, scale,
                        neighbour_pairs(frame.mesh, *frame.surface, atlas.width, centres, density, n, directions), n);
  row.emplace_back("layout_neighbour_correlation", near.atlas);
  row.emplace_back("layout_neighbour_correlation_exemplar", near.exemplar);
  row.emplace_back("layout_neighbour_correlation_excess", near.excess);
  row.emplace_back("layout_neighbour_pairs", near.pairs);
}

/// How much the atlas still looks like its exemplar at `scale`
/// (appearance_metrics.h): orientation and nearest-window energy on the
/// surface in `directions`, and the colour distribution.
void appearance_figures(const Image& atlas, const UVMesh& mesh, const std::vector<char>& mask, const Exemplar& exemplar,
                        double scale, const DirectionFrame& directions, MetricRow& row) {
  const OrientationFigures o = orientation_figures(atlas, mesh, mask, exemplar, scale, directions);
  row.emplace_back("orientation_coherence", o.coherence);
  row.emplace_back("orientation_coherence_exemplar", o.exemplar_coherence);
  row.emplace_back("orientation_coherence_ratio", o.coherence_ratio);
  row.emplace_back("orientation_histogram_distance", o.histogram_distance);
  row.emplace_back("orientation_histogram_distance_aligned", o.aligned_histogram_distance);
  row.emplace_back("orientation_angle_deg", o.angle_deg);
  row.emplace_back("orientation_window", o.window);
  row.emplace_back("window_energy_ratio", window_energy_ratio(atlas, mesh, mask, exemplar, scale, directions));
  row.emplace_back("histogram_distance", value_histogram_distance(atlas, mask, exemplar, scale));
}

/// Contrast, spectrum and appearance of the atlas the run wrote (of UDIM
/// tiles, 1001), against the exemplar at the atlas's texel density, and the
/// exemplar's size on the surface asked for and measured. The layout's
/// autocorrelation is read at the spacing of the live disk `centres`
/// (mean_nearest_distance), or at the disk radius d where there are none
/// (a flow map), so that runs compare at about the same lag. Returns the
/// scale it measured at (exemplar texels per atlas texel; NaN without uv
/// area).
double texture_figures(const TexturedFrame& frame, const TrackingOptions& resolved, const JobOptions& job,
                       const Exemplar& exemplar, const std::vector<Vec3>& centres, MetricRow& row) {
  const SynthesisJobOptions& so = job.synthesis;
  const Image& atlas = frame.atlas.first();
  const std::vector<char> mask = chart_mask(frame.mesh, atlas.width);
  const double density = texel_density(frame.mesh, atlas.width);
  double scale = exemplar_scale(resolved, so, exemplar, density);     // exemplar texels per atlas texel
  if (!std::isfinite(scale) || !(scale > 0.0)) scale = std::nan("");  // no uv area
  const std::vector<double> contrast = std::isnan(scale) ? std::vector<double>(exemplar.channels(), std::nan(""))
                                                         : contrast_ratio(atlas, mask, exemplar, scale);
  const char* channel[] = {"contrast_r", "contrast_g", "contrast_b"};
  for (std::size_t c = 0; c < contrast.size(); ++c)
    row.emplace_back(contrast.size() == 1 ? "contrast" : channel[c], contrast[c]);
  row.emplace_back("texel_density", density);
  spectrum_figures(atlas, mask, exemplar, scale, row);
  const DirectionFrame directions = direction_frame(job.flowmap);
  appearance_figures(atlas, frame.mesh, mask, exemplar, scale, directions, row);
  const double spacing = mean_nearest_distance(centres);
  const double lag = (std::isfinite(spacing) ? spacing : resolved.d()) * density;  // atlas texels
  patch_layout_figures(frame, mask, exemplar, scale, lag, density, centres, directions, row);
  // The exemplar's size on the surface: what the job asked for, and what
  // the atlas shows through the UV mesh.
  const double span = exemplar_span(resolved, so);
  row.emplace_back("exemplar_size", span);
  row.emplace_back("exemplar_size_measured", measured_exemplar_span(atlas, frame.mesh, exemplar, span));
  return scale;
}

/// Texture–flow agreement of two frames measured: warping error and optical
/// flow against the liquid's projected motion.
void flow_figures(const FrameMesh& previous_mesh, const TexturedFrame& previous, const TexturedFrame& current,
                  const LiquidMotion& motion, const Exemplar& exemplar, const EvalOptions& options, int frame,
                  MetricRow& row) {
  const WarpingError w =
      warping_error(previous_mesh, previous, current, motion, exemplar, options.samples, options.seed + frame);
  row.emplace_back("warp_advected", w.advected);
  row.emplace_back("warp_fixed", w.fixed);
  row.emplace_back("warp_random", w.random);
  if (options.flow_width > 0) {
    RenderOptions render = options.render;
    render.width = options.flow_width;
    const FlowError f =
        flow_against_velocity(previous_mesh, previous, current, motion, render, options.flow_max_motion);
    row.emplace_back("flow_endpoint_px", f.pixels ? f.endpoint : std::nan(""));
    row.emplace_back("flow_angular_deg", f.pixels ? f.angular : std::nan(""));
    row.emplace_back("flow_speed_px", f.pixels ? f.speed : std::nan(""));
    row.emplace_back("flow_slow_endpoint_px", f.slow_pixels ? f.slow_endpoint : std::nan(""));
    row.emplace_back("flow_slow_speed_px", f.slow_pixels ? f.slow_speed : std::nan(""));
    row.emplace_back("flow_slow_share", f.pixels ? static_cast<double>(f.slow_pixels) / f.pixels : std::nan(""));
  }
}

/// Means over the frames measured of every key, and the mean patch lifetime.
MetricRow summarize(const std::vector<MetricRow>& rows, const std::vector<double>& lifetimes) {
  MetricRow summary{{"frames", static_cast<double>(rows.size())}};
  std::vector<std::string> keys;
  for (const MetricRow& r : rows) {
    for (const auto& [k, v] : r) {
      if (k != "frame" && k != "spectrum_crop" && k != "orientation_window" &&
          std::find(keys.begin(), keys.end(), k) == keys.end())
        keys.push_back(k);
    }
  }
  for (const std::string& k : keys) {
    double sum = 0.0;
    int n = 0;
    for (const MetricRow& r : rows) {
      const double v = metric_value(r, k);
      if (std::isfinite(v)) sum += v, ++n;
    }
    summary.emplace_back(k == "uncovered_area" || k == "uncovered_texels" ? k + "_mean" : k,
                         n ? sum / n : std::nan(""));
  }
  summary.emplace_back(
      "patch_lifetime_mean",
      lifetimes.empty() ? std::nan("") : std::accumulate(lifetimes.begin(), lifetimes.end(), 0.0) / lifetimes.size());
  return summary;
}

/// `frame`'s outputs rendered to `pattern`'s PNG for the report; returns its path.
std::string write_render(const TexturedFrame& outputs, int frame, const std::string& pattern,
                         const RenderOptions& render) {
  std::string png = FramePattern(pattern).path(frame);
  write_image(png, render_textured(outputs.mesh, outputs.atlas, render), ImageWriteOptions{});
  return png;
}

/// In the report's gallery: the exemplar at the surface's `scale` (once,
/// with the first frame) and a view of `outputs`' atlas the same size as
/// the surface shows it in `directions` (surface_view): the first window of
/// 256² (or 128² .. 32² where none fits) whose turned square lies inside its
/// charts, to DIR/exemplar_at_scale.png and DIR/gallery.####.png.
void add_gallery(const TexturedFrame& outputs, int frame, double scale, const Exemplar& exemplar,
                 const DirectionFrame& directions, const std::string& dir, EvalReport& report) {
  const Image& atlas = outputs.atlas.first();
  const std::vector<char> mask = chart_mask(outputs.mesh, atlas.width);
  for (int n = 256; n >= 32; n /= 2) {
    const int reach = static_cast<int>(std::ceil(n * M_SQRT2));  // the turned window's
    const auto windows = chart_windows(mask, atlas.width, reach, 1);
    if (windows.empty()) continue;
    if (report.gallery.empty() && std::isfinite(scale)) {
      const std::string png = dir + "/exemplar_at_scale.png";
      write_image(png, exemplar_crop(exemplar, 0.0, 0.0, scale, n));
      char caption[96];
      std::snprintf(caption, sizeof caption, "the exemplar at the surface's scale (%.3g exemplar texels per texel)",
                    scale);
      report.gallery.emplace_back(png, caption);
    }
    const Vec2 centre(windows.front().first + 0.5 * reach, windows.front().second + 0.5 * reach);
    const auto map = window_frames(outputs.mesh, atlas.width, windows, reach, directions).front();
    const std::string png = FramePattern(dir + "/gallery.####.png").path(frame);
    write_image(png, surface_view(atlas, centre, map, n));
    report.gallery.emplace_back(png, "frame " + std::to_string(frame) +
                                         ", as the surface shows it around atlas texel (" +
                                         std::to_string(static_cast<int>(centre.x())) + ", " +
                                         std::to_string(static_cast<int>(centre.y())) + ")");
    return;
  }
}

/// The report's images of the `i`-th of `count` frames: a preview render
/// every count / options.report_images frames (at most
/// options.report_images), and the gallery's crops of the first, middle and
/// last frames.
void add_report_images(const TexturedFrame& outputs, int frame, std::size_t i, std::size_t count, double scale,
                       const Exemplar& exemplar, const JobOptions& job, const EvalOptions& options,
                       const std::string& dir, EvalReport& report) {
  const std::size_t every =
      std::max<std::size_t>(1, count / static_cast<std::size_t>(std::max(1, options.report_images)));
  if (i % every == 0 && static_cast<int>(report.images.size()) < options.report_images)
    report.images.push_back(write_render(outputs, frame, dir + "/preview.####.png", options.render));
  if (i == 0 || i == count / 2 || i + 1 == count)
    add_gallery(outputs, frame, scale, exemplar, direction_frame(job.flowmap), dir, report);
}

/// The worst frame of each range where a figure is bad (at most
/// kWorstImages), rendered to DIR/worst.####.png for the report.
std::vector<std::string> render_worst_frames(const Verdict& verdict, const std::string& atlas_pattern,
                                             const std::string& mesh_pattern, const std::string& dir,
                                             const RenderOptions& render) {
  std::vector<std::string> images;
  for (const VerdictRange& r : verdict.ranges) {
    if (static_cast<int>(images.size()) == kWorstImages) break;
    images.push_back(
        write_render(read_run_frame(atlas_pattern, mesh_pattern, r.worst), r.worst, dir + "/worst.####.png", render));
  }
  return images;
}

/// The frames a sequence is read from: its own and those on disk between
/// them (followed), and the liquid's motion from one frame to another
/// through them.
class FollowedFrames {
 public:
  explicit FollowedFrames(const Sequence& sequence) : read_(sequence.followed()) {}

  std::shared_ptr<const FrameMesh> mesh(int frame) const {
    return load(std::lower_bound(read_.frames().begin(), read_.frames().end(), frame));
  }

  LiquidMotion motion_between(int from, int to) const {
    const std::vector<int>& followed = read_.frames();
    const auto first = std::upper_bound(followed.begin(), followed.end(), from);
    const auto last = std::lower_bound(first, followed.end(), to);
    LiquidMotion motion((first == last ? to - from : *first - from) / read_.fps());
    for (auto it = first; it != last; ++it) {
      const int next = it + 1 == last ? to : *(it + 1);
      motion.add_step(load(it), (next - *it) / read_.fps());
    }
    return motion;
  }

 private:
  std::shared_ptr<const FrameMesh> load(std::vector<int>::const_iterator at) const {
    return std::make_shared<const FrameMesh>(read_.load(static_cast<std::size_t>(at - read_.frames().begin())));
  }

  Sequence read_;
};

/// OUT/eval/: per-frame lines, a summary (means over the frames measured),
/// the verdict and the report (`report` with its rows and previews; the
/// worst frames rendered here).
EvalSummary write_eval_outputs(const EvalOptions& options, const std::string& atlas_pattern,
                               const std::string& mesh_pattern, EvalReport report, const PatchHistory& history) {
  const std::string dir = options.run_dir + "/eval";
  std::string lines;
  for (const MetricRow& r : report.rows) lines += to_json_object(r) + "\n";
  write_text_atomically(dir + "/metrics.jsonl", lines);
  report.summary = summarize(report.rows, history.lifetimes());
  write_text_atomically(dir + "/summary.json", to_json_object(report.summary) + "\n");
  report.verdict = judge(report.rows, options.thresholds);
  write_text_atomically(dir + "/verdict.json", verdict_json(report.verdict));
  report.worst_images = render_worst_frames(report.verdict, atlas_pattern, mesh_pattern, dir, options.render);
  report.retired = history.retired_by_age();
  write_text_atomically(dir + "/report.html", html_report(report));
  return EvalSummary{report.rows.size(), dir + "/report.html", report.verdict};
}

}  // namespace

EvalSummary run_eval(const EvalOptions& options, const JobOptions& job_in, Reporter& reporter) {
  JobOptions job = job_in;
  job.output.dir = options.run_dir;
  const std::string atlas_pattern = job.output.atlas(), mesh_pattern = job.output.mesh();
  // The frames on disk between two measured ones (a stepped run's skipped
  // frames, followed or not) carry the liquid from one to the next.
  InputOptions input = options.input;
  input.skipped_frames = SkippedFrames::Follow;
  const Sequence sequence(input);
  const FollowedFrames read(sequence);
  if (!options.exemplar.empty()) job.exemplar = options.exemplar;
  // The exemplar in the space the atlases are in (managed: the output space).
  const TextureSource source = load_texture_source(job);
  const Exemplar exemplar(source.colors.to_output(source.exemplar.image()));
  const std::string dir = options.run_dir + "/eval";
  std::filesystem::create_directories(dir);

  // The run's resolved lengths: from a state file when there is one, else
  // resolved on the first frame as the run did.
  std::optional<TrackingOptions> resolved;
  EvalReport report;
  report.run_dir = options.run_dir;
  PatchHistory history;
  ChangeHistory change;
  std::optional<TexturedFrame> previous;
  std::shared_ptr<const FrameMesh> previous_mesh;
  for (std::size_t i = 0; i < sequence.size(); ++i) {
    const int frame = sequence.frames()[i];
    reporter.progress(i, sequence.size(), "eval");
    // Read among the frames between (velocities from positions are central
    // differences over them, as a run that follows them reads them).
    auto mesh = read.mesh(frame);
    TexturedFrame current = read_run_frame(atlas_pattern, mesh_pattern, frame);
    MetricRow row{{"frame", frame}};
    const std::string state = state_path(options.run_dir, frame);
    std::vector<Vec3> centres;  // the live disks', where the frame has patches
    if (std::filesystem::exists(state)) {
      const Tracker tracker = Tracker::load(state, mesh, frame);
      if (!resolved) resolved = tracker.settings().tracking;
      history.add(frame, tracker, row);
      change.add(frame, tracker, sequence.fps(), row);
      patch_figures(tracker, job, exemplar, row);
      centres = live_centres(tracker.patches());
    }
    if (!resolved) resolved = job.tracking.resolved(bounding_box(*mesh).diagonal());
    const double scale = texture_figures(current, *resolved, job, exemplar, centres, row);
    if (previous) {
      const LiquidMotion motion = read.motion_between(sequence.frames()[i - 1], frame);
      flow_figures(*previous_mesh, *previous, current, motion, exemplar, options, frame, row);
    }
    add_report_images(current, frame, i, sequence.size(), scale, exemplar, job, options, dir, report);
    report.rows.push_back(std::move(row));
    previous.emplace(std::move(current));
    previous_mesh = mesh;
  }
  history.finish(sequence.frames().back());
  EvalSummary out = write_eval_outputs(options, atlas_pattern, mesh_pattern, std::move(report), history);
  reporter.progress(sequence.size(), sequence.size(), "eval");
  return out;
}

}  // namespace fluidtex
