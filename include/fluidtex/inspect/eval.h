/// @file eval.h
/// @brief `fluidtex eval`: how good a finished run is, measured per frame
/// from its outputs (atlas + UV mesh), its patch states and the input
/// sequence: coverage, ghosting, patch life, distortion, texture–flow
/// agreement (warping error and optical flow against the fluid velocity),
/// contrast, spectrum and appearance against the exemplar. Writes
/// OUT/eval/metrics.jsonl, summary.json, the verdict (verdict.json,
/// verdict.h) and a self-contained report.html.
///
/// The figures come from texture_metrics.h (contrast, spectrum),
/// appearance_metrics.h (orientation, nearest-window energy, colour
/// histogram), motion_metrics.h (warping error, optical flow) and
/// patch_history.h (patch life, surface made and destroyed); eval_report.h
/// draws the page.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "fluidtex/inspect/motion_metrics.h"
#include "fluidtex/inspect/render.h"
#include "fluidtex/inspect/verdict.h"
#include "fluidtex/job/job_options.h"
#include "fluidtex/util/report.h"
#include "fluidtex/util/shared_options.h"

namespace fluidtex {

struct EvalOptions {
  std::string run_dir;   ///< -o: the finished run's folder
  InputOptions input;    ///< -i: the input sequence the run used
  std::string exemplar;  ///< -e; empty = the run's (from OUT/job.toml)
  int samples = 20000;   ///< warping-error sample points per frame pair
  std::uint64_t seed = 1;
  int flow_width = 512;                       ///< render width for the optical-flow metric (0 = off)
  double flow_max_motion = kFlowMaxMotionPx;  ///< pixels per frame; faster pixels are left out of the slow_ flow means
  int report_images = 4;                      ///< preview images in the report
  RenderOptions render;                       ///< camera of the flow renders and report images
  EvalThresholds thresholds;                  ///< the verdict's good / warn / bad bounds

  /// The options of `eval` as f(OptionInfo, field) (util/options.h); the
  /// thresholds have their own table (EvalThresholds).
  template <class Self, class F>
  static void for_each_option(Self& o, F&& f) {
    using namespace shared_options;
    f(with_help(kInput, "The input sequence (default: the run's, from job.toml)"), o.input.pattern);
    f(required(kOutput, "The run's output folder (with job.toml)"), o.run_dir);
    f(with_help(kFrames, "Frames to evaluate (default: the run's)"), o.input.frames);
    f(with_help(kExemplar, "Exemplar (default: the run's, from job.toml)"), o.exemplar);
    f(with_help(kSamples, "Warping-error sample points per frame pair"), o.samples);
    f(with_help(kSeed, "Seed of the sample points"), o.seed);
    f(OptionInfo{.name = "flow-width",
                 .help = "Render width for the optical-flow metric (0: skip it)",
                 .bounds = between(0, 8192)},
      o.flow_width);
    f(OptionInfo{.name = "flow-max-motion",
                 .help = "Projected motion (pixels per frame of the flow renders) from which a pixel is left out of "
                         "the flow_slow_ figures: the optical flow is unreliable beyond",
                 .bounds = between(1e-9, 1e9)},
      o.flow_max_motion);
    f(OptionInfo{.name = "images", .help = "Preview images in the report", .bounds = between(0, 1000)},
      o.report_images);
    f(with_help(kView, "Orthographic view of the renders: top, front, side"), o.render.view);
  }
};

struct EvalSummary {
  std::size_t frames = 0;
  std::string report;  ///< path of report.html
  Verdict verdict;     ///< also in OUT/eval/verdict.json and at the top of the report
};

/// Evaluates the run in options.run_dir made with `job` (read from its
/// job.toml by the caller). InputError for missing or unreadable outputs.
EvalSummary run_eval(const EvalOptions& options, const JobOptions& job, Reporter& reporter);

}  // namespace fluidtex
