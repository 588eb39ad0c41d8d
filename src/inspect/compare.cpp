#include "fluidtex/inspect/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <oneapi/tbb/parallel_for.h>

#include "fluidtex/inspect/motion_metrics.h"
#include "fluidtex/inspect/textured_frame.h"
#include "fluidtex/job/job_record.h"
#include "fluidtex/util/error.h"

namespace fluidtex {

namespace {

/// A run's frames and the patterns of its atlases and UV meshes.
struct RunFiles {
  std::vector<int> frames;
  std::string atlas, mesh;
};

RunFiles run_files(const std::string& dir) {
  if (!std::filesystem::is_directory(dir)) throw InputError(dir, "not a folder (expected a fluidtex output folder)");
  JobRecord record = read_job_record(dir);
  if (record.options.synthesis.track_only)
    throw InputError(job_record_path(dir), "a --track-only job has no atlases to compare");
  record.options.output.dir = dir;
  RunFiles files{record.frames, record.options.output.atlas(), record.options.output.mesh()};
  return files;
}

FrameComparison compare_frame(const TexturedFrame& golden, const TexturedFrame& candidate, int frame,
                              const CompareOptions& options) {
  const auto points = surface_samples(*golden.geometry, options.samples, options.seed, 7);
  const int channels = golden.atlas.channels;
  std::vector<double> difference(points.size());
  tbb::parallel_for(std::size_t(0), points.size(), [&](std::size_t i) {
    const auto& [f, bary] = points[i];
    const Vec3 p = interpolate(golden.geometry->positions, golden.geometry->triangles[f], bary);
    float a[kMaxLookupChannels], b[kMaxLookupChannels];
    golden.color_at(p, a);
    candidate.color_at(p, b);
    double sum = 0.0;
    for (int c = 0; c < channels; ++c) sum += std::abs(double(a[c]) - double(b[c]));
    difference[i] = sum / channels;
  });
  FrameComparison out;
  out.frame = frame;
  out.samples = difference.size();
  if (difference.empty()) return out;
  double total = 0.0;
  for (double d : difference) total += d;
  out.mean = total / static_cast<double>(difference.size());
  std::sort(difference.begin(), difference.end());
  const auto rank =
      static_cast<std::size_t>(std::ceil(options.percentile / 100.0 * static_cast<double>(difference.size())));
  out.percentile = difference[std::min(difference.size() - 1, rank > 0 ? rank - 1 : 0)];
  out.max = difference.back();
  out.passed = out.mean <= options.mean_tolerance && out.percentile <= options.percentile_tolerance;
  return out;
}

}  // namespace

Comparison compare_runs(const CompareOptions& options, Reporter& reporter) {
  const RunFiles golden = run_files(options.golden);
  const RunFiles candidate = run_files(options.candidate);
  if (golden.frames != candidate.frames) {
    throw InputError(job_record_path(options.candidate), "covers frames " + format_frame_range(candidate.frames) +
                                                             ", the golden run " + format_frame_range(golden.frames) +
                                                             " (compare runs of the same frames)");
  }
  Comparison out;
  for (std::size_t i = 0; i < golden.frames.size(); ++i) {
    const int frame = golden.frames[i];
    reporter.progress(i, golden.frames.size(), "compare");
    const TexturedFrame a = read_run_frame(golden.atlas, golden.mesh, frame);
    const TexturedFrame b = read_run_frame(candidate.atlas, candidate.mesh, frame);
    if (a.atlas.channels != b.atlas.channels) {
      throw InputError(
          FramePattern(candidate.atlas).path(frame),
          std::to_string(b.atlas.channels) + " channels, the golden atlas " + std::to_string(a.atlas.channels));
    }
    out.frames.push_back(compare_frame(a, b, frame, options));
    out.passed = out.passed && out.frames.back().passed;
  }
  reporter.progress(golden.frames.size(), golden.frames.size(), "compare");
  return out;
}

namespace {

std::string percentile_name(const CompareOptions& options) {
  char name[32];
  std::snprintf(name, sizeof name, "p%g", options.percentile);
  return name;
}

}  // namespace

std::string comparison_verdict(const Comparison& comparison, const CompareOptions& options) {
  const auto failed = std::count_if(comparison.frames.begin(), comparison.frames.end(),
                                    [](const FrameComparison& f) { return !f.passed; });
  char verdict[200];
  std::snprintf(verdict, sizeof verdict, "%s: %ld of %zu frames differ (mean > %g or %s > %g)\n",
                comparison.passed ? "same" : "differs", static_cast<long>(failed), comparison.frames.size(),
                options.mean_tolerance, percentile_name(options).c_str(), options.percentile_tolerance);
  return verdict;
}

std::string format_comparison(const Comparison& comparison, const CompareOptions& options) {
  std::ostringstream s;
  s << "| frame | samples | mean | " << percentile_name(options) << " | max | |\n|---|---|---|---|---|---|\n";
  for (const FrameComparison& f : comparison.frames) {
    char line[160];
    std::snprintf(line, sizeof line, "| %d | %zu | %.5f | %.5f | %.5f | %s |\n", f.frame, f.samples, f.mean,
                  f.percentile, f.max, f.passed ? "ok" : "DIFFERS");
    s << line;
  }
  s << comparison_verdict(comparison, options);
  return s.str();
}

}  // namespace fluidtex
