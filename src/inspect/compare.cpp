#include "fluidtex/inspect/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <sstream>

#include <oneapi/tbb/parallel_for.h>

#include "fluidtex/inspect/motion_metrics.h"
#include "fluidtex/inspect/texture_metrics.h"
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
  const int channels = golden.atlas.first().channels;
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

/// Whether two frames share their layout: the same atlas tiles and sizes
/// and the same UV mesh, so that texel (x, y) of a tile of one is texel
/// (x, y) of that tile of the other.
bool same_layout(const TexturedFrame& a, const TexturedFrame& b) {
  if (a.atlas.udims != b.atlas.udims || a.atlas.udim != b.atlas.udim) return false;
  for (std::size_t t = 0; t < a.atlas.tiles.size(); ++t) {
    if (a.atlas.tiles[t].width != b.atlas.tiles[t].width || a.atlas.tiles[t].height != b.atlas.tiles[t].height)
      return false;
  }
  return a.mesh.uvs == b.mesh.uvs && a.mesh.uv_triangles == b.mesh.uv_triangles &&
         a.mesh.positions == b.mesh.positions && a.mesh.triangles == b.mesh.triangles;
}

/// The surface point that texel (x, y) of `frame`'s atlas tile `t` shows:
/// its centre in the uv triangle that holds it (a gutter texel: in the
/// nearest one, extended).
Vec3 texel_point(const TexturedFrame& frame, std::size_t t, int x, int y) {
  const Image& tile = frame.atlas.tiles[t];
  const Vec2 q = udim_origin(frame.atlas.udims[t]) + Vec2(px_to_u(x + 0.5, tile.width), py_to_v(y + 0.5, tile.height));
  double best = std::numeric_limits<double>::infinity();
  Vec3 out = Vec3::Zero();
  for (std::size_t f = 0; f < frame.mesh.uv_triangles.size(); ++f) {
    const Tri& tri = frame.mesh.uv_triangles[f];
    const Vec2 &a = frame.mesh.uvs[tri[0]], &b = frame.mesh.uvs[tri[1]], &c = frame.mesh.uvs[tri[2]];
    const double area = signed_area(a, b, c);
    if (area == 0.0) continue;
    const Vec3 l(signed_area(q, b, c) / area, signed_area(a, q, c) / area, signed_area(a, b, q) / area);
    const double outside = -std::min({l.x(), l.y(), l.z(), 0.0});
    if (outside < best) {
      best = outside;
      out = interpolate(frame.mesh.positions, frame.mesh.triangles[f], l);
    }
  }
  return out;
}

/// The texel-by-texel part of a comparison of two frames of one layout:
/// every chart texel of every tile, the largest difference in any channel.
void compare_texels(const TexturedFrame& golden, const TexturedFrame& candidate, FrameComparison& out) {
  std::size_t worst = 0, worst_tile = 0;
  for (std::size_t t = 0; t < golden.atlas.tiles.size(); ++t) {
    const Image& a = golden.atlas.tiles[t];
    const Image& b = candidate.atlas.tiles[t];
    const std::vector<char> charts = chart_mask(golden.mesh, a.width, udim_origin(golden.atlas.udims[t]));
    for (std::size_t i = 0; i < charts.size(); ++i) {
      if (!charts[i]) continue;
      ++out.texels;
      for (int c = 0; c < a.channels; ++c) {
        double d = std::abs(double(a.pixel(i)[c]) - double(b.pixel(i)[c]));
        if (std::isnan(d)) d = std::numeric_limits<double>::infinity();
        if (d > out.texel_max) {
          out.texel_max = d;
          worst = i;
          worst_tile = t;
        }
      }
    }
  }
  const int width = golden.atlas.tiles[worst_tile].width;
  out.worst_udim = golden.atlas.udim ? golden.atlas.udims[worst_tile] : 0;
  out.worst_x = static_cast<int>(worst % width);
  out.worst_y = static_cast<int>(worst / width);
  if (out.texel_max > 0.0) out.worst_point = texel_point(golden, worst_tile, out.worst_x, out.worst_y);
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
    if (a.atlas.first().channels != b.atlas.first().channels) {
      throw InputError(FramePattern(candidate.atlas).first_file(frame), std::to_string(b.atlas.first().channels) +
                                                                            " channels, the golden atlas " +
                                                                            std::to_string(a.atlas.first().channels));
    }
    FrameComparison f = compare_frame(a, b, frame, options);
    if (same_layout(a, b)) {
      compare_texels(a, b, f);
      f.passed = f.passed && f.texel_max <= options.max_tolerance;
    }
    out.passed = out.passed && f.passed;
    out.frames.push_back(f);
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
  std::snprintf(verdict, sizeof verdict, "%s: %ld of %zu frames differ (mean > %g or %s > %g or a texel > %g)\n",
                comparison.passed ? "same" : "differs", static_cast<long>(failed), comparison.frames.size(),
                options.mean_tolerance, percentile_name(options).c_str(), options.percentile_tolerance,
                options.max_tolerance);
  return verdict;
}

std::string format_comparison(const Comparison& comparison, const CompareOptions& options) {
  std::ostringstream s;
  s << "| frame | samples | mean | " << percentile_name(options)
    << " | max | texel max | |\n|---|---|---|---|---|---|---|\n";
  for (const FrameComparison& f : comparison.frames) {
    char line[200], texel[32] = "layouts differ";
    if (f.texels > 0) std::snprintf(texel, sizeof texel, "%.5f", f.texel_max);
    std::snprintf(line, sizeof line, "| %d | %zu | %.5f | %.5f | %.5f | %s | %s |\n", f.frame, f.samples, f.mean,
                  f.percentile, f.max, texel, f.passed ? "ok" : "DIFFERS");
    s << line;
  }
  for (const FrameComparison& f : comparison.frames) {
    if (f.texels == 0 || f.texel_max <= options.max_tolerance) continue;
    char line[240], tile[24] = "";
    if (f.worst_udim > 0) std::snprintf(tile, sizeof tile, " of tile %d", f.worst_udim);
    std::snprintf(line, sizeof line,
                  "frame %d: worst texel (%d, %d)%s differs by %.5f, at (%.6g, %.6g, %.6g) on the surface\n", f.frame,
                  f.worst_x, f.worst_y, tile, f.texel_max, f.worst_point.x(), f.worst_point.y(), f.worst_point.z());
    s << line;
  }
  s << comparison_verdict(comparison, options);
  return s.str();
}

}  // namespace fluidtex
