#include "fluidtex/inspect/info.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "fluidtex/tracking/options.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/json.h"

namespace fluidtex {

FrameInfo inspect_frame(const Sequence& sequence, std::size_t index) {
  FrameInfo info;
  info.frame = sequence.frames().at(index);
  info.path = sequence.path_of(info.frame);
  try {
    const FrameMesh mesh = sequence.load(index, &info.clean);
    info.vertices = mesh.num_vertices();
    info.faces = mesh.num_faces();
    info.bbox = bounding_box(mesh);
    info.area = surface_area(mesh);
    info.mean_edge = mean_edge_length(mesh);
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0, sum = 0.0;
    for (const Vec3& v : mesh.velocities) {
      const double s = v.norm();
      lo = std::min(lo, s);
      hi = std::max(hi, s);
      sum += s;
    }
    info.speed_min = mesh.velocities.empty() ? 0.0 : lo;
    info.speed_max = hi;
    info.speed_mean = mesh.velocities.empty() ? 0.0 : sum / static_cast<double>(mesh.velocities.size());
  } catch (const InputError& e) {
    info.error = e.what();
  }
  return info;
}

namespace {

/// One frame's row of the table: its counts and sizes, and as notes its
/// components and what cleaning did (or its error).
std::string frame_row(const FrameInfo& f) {
  char line[512];
  if (!f.error.empty()) {
    std::snprintf(line, sizeof line, "%7d  ERROR %s\n", f.frame, f.error.c_str());
    return line;
  }
  std::string notes = f.clean.components > 1 ? std::to_string(f.clean.components) + " components" : "";
  if (f.clean.changed() || f.clean.nonmanifold_edges > 0) {
    if (!notes.empty()) notes += "; ";
    notes += f.clean.summary();
  }
  std::snprintf(line, sizeof line, "%7d %9zu %9zu %10.4g %10.4g %10.4g %10.4g  %s\n", f.frame, f.vertices, f.faces,
                f.area, f.mean_edge, f.speed_max, f.speed_mean, notes.c_str());
  return line;
}

}  // namespace

std::optional<TextureScale> default_texture_scale(const std::vector<FrameInfo>& frames) {
  const auto first = std::find_if(frames.begin(), frames.end(), [](const FrameInfo& f) { return f.error.empty(); });
  if (first == frames.end() || !(first->bbox.diagonal() > 0.0)) return std::nullopt;
  const TrackingOptions resolved = TrackingOptions{}.resolved(first->bbox.diagonal());
  TextureScale scale;
  scale.radius = resolved.d();
  scale.exemplar_size = resolved.exemplar_tile_size() / resolved.uv_scale;
  // Two significant digits: a value to write into a show's settings.
  const double unit = std::pow(10.0, std::floor(std::log10(scale.exemplar_size)) - 1.0);
  scale.suggested_exemplar_size = std::round(scale.exemplar_size / unit) * unit;
  return scale;
}

namespace {

/// What info says of the texture's default size and the --exemplar-size to
/// give (empty when no frame is readable).
std::string texture_scale_line(const std::vector<FrameInfo>& frames) {
  const std::optional<TextureScale> scale = default_texture_scale(frames);
  if (!scale) return "";
  char line[256];
  std::snprintf(line, sizeof line,
                "texture size: by default one exemplar tile spans %.4g scene units (%.3g x --radius %.4g, from the "
                "first frame's size); to give every shot the same, set --exemplar-size (e.g. %.2g)\n",
                scale->exemplar_size, scale->exemplar_size / scale->radius, scale->radius,
                scale->suggested_exemplar_size);
  return line;
}

}  // namespace

std::string format_info(const std::vector<FrameInfo>& frames, double fps, FpsSource fps_source) {
  std::string out;
  char line[512];
  std::snprintf(line, sizeof line, "%7s %9s %9s %10s %10s %10s %10s  %s\n", "frame", "vertices", "faces", "area",
                "edge", "|v| max", "|v| mean", "notes");
  out += line;
  std::size_t bad = 0, nonmanifold = 0, cleaned = 0;
  BBox all;
  bool first = true;
  double speed_lo = std::numeric_limits<double>::infinity(), speed_hi = 0.0;
  std::size_t vmin = std::numeric_limits<std::size_t>::max(), vmax = 0, fmin = vmin, fmax = 0;
  int comp_max = 0;
  for (const FrameInfo& f : frames) {
    out += frame_row(f);
    if (!f.error.empty()) {
      ++bad;
      continue;
    }
    if (f.clean.changed()) ++cleaned;
    if (f.clean.nonmanifold_edges > 0) ++nonmanifold;
    if (first) {
      all = f.bbox;
      first = false;
    } else {
      all.min = all.min.cwiseMin(f.bbox.min);
      all.max = all.max.cwiseMax(f.bbox.max);
    }
    speed_lo = std::min(speed_lo, f.speed_min);
    speed_hi = std::max(speed_hi, f.speed_max);
    vmin = std::min(vmin, f.vertices), vmax = std::max(vmax, f.vertices);
    fmin = std::min(fmin, f.faces), fmax = std::max(fmax, f.faces);
    comp_max = std::max(comp_max, f.clean.components);
  }
  const std::size_t good = frames.size() - bad;
  const char* from = fps_source == FpsSource::Header    ? " (as the first frame's header states)"
                     : fps_source == FpsSource::Default ? " (the default: the first frame states none; --fps sets it)"
                                                        : "";
  std::snprintf(line, sizeof line, "\n%zu frames (%d..%d), %zu readable, %zu with errors; fps %g%s\n", frames.size(),
                frames.empty() ? 0 : frames.front().frame, frames.empty() ? 0 : frames.back().frame, good, bad, fps,
                from);
  out += line;
  if (good > 0) {
    std::snprintf(line, sizeof line,
                  "vertices %zu..%zu, faces %zu..%zu, up to %d components\n"
                  "bounding box (%.4g, %.4g, %.4g) - (%.4g, %.4g, %.4g), diagonal %.4g\n"
                  "|velocity| %.4g..%.4g scene units/s (%.4g..%.4g per frame)\n",
                  vmin, vmax, fmin, fmax, comp_max, all.min.x(), all.min.y(), all.min.z(), all.max.x(), all.max.y(),
                  all.max.z(), all.diagonal(), speed_lo, speed_hi, speed_lo / fps, speed_hi / fps);
    out += line;
  }
  out += texture_scale_line(frames);
  std::snprintf(line, sizeof line, "problems: %zu unreadable, %zu cleaned, %zu non-manifold\n", bad, cleaned,
                nonmanifold);
  out += line;
  return out;
}

namespace {

std::string json_vec3(const Vec3& v) {
  return "[" + json_number(v.x()) + "," + json_number(v.y()) + "," + json_number(v.z()) + "]";
}

}  // namespace

std::string format_info_json(const std::vector<FrameInfo>& frames, double fps, FpsSource fps_source,
                             const std::string& pattern) {
  std::size_t errors = 0;
  std::string out = "{\"sequence\":" + json_string(pattern) + ",\"fps\":" + json_number(fps) +
                    ",\"fps_source\":" + json_string(enum_name(fps_source)) + ",\"frames\":[";
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const FrameInfo& f = frames[i];
    errors += f.error.empty() ? 0 : 1;
    const auto count = [](std::size_t n) { return static_cast<double>(n); };
    out += i ? "," : "";
    out += "{\"frame\":" + std::to_string(f.frame) + ",\"path\":" + json_string(f.path);
    out += ",\"error\":" + (f.error.empty() ? std::string("null") : json_string(f.error));
    out += ",\"vertices\":" + std::to_string(f.vertices) + ",\"faces\":" + std::to_string(f.faces);
    out += ",\"bbox\":{\"min\":" + json_vec3(f.bbox.min) + ",\"max\":" + json_vec3(f.bbox.max) + "}";
    out += ",\"area\":" + json_number(f.area) + ",\"mean_edge\":" + json_number(f.mean_edge);
    out += ",\"speed\":" + to_json_object({{"min", f.speed_min}, {"max", f.speed_max}, {"mean", f.speed_mean}});
    out += ",\"clean\":" + to_json_object({{"merged_vertices", count(f.clean.merged_vertices)},
                                           {"degenerate_faces", count(f.clean.degenerate_faces)},
                                           {"duplicate_faces", count(f.clean.duplicate_faces)},
                                           {"unreferenced_vertices", count(f.clean.unreferenced_vertices)},
                                           {"nonmanifold_edges", count(f.clean.nonmanifold_edges)},
                                           {"boundary_edges", count(f.clean.boundary_edges)},
                                           {"components", static_cast<double>(f.clean.components)}});
    out += "}";
  }
  out += "],\"errors\":" + std::to_string(errors);
  if (const std::optional<TextureScale> scale = default_texture_scale(frames)) {
    out += ",\"texture_scale\":" + to_json_object({{"radius", scale->radius},
                                                   {"exemplar_size", scale->exemplar_size},
                                                   {"suggested_exemplar_size", scale->suggested_exemplar_size}});
  }
  out += "}\n";
  return out;
}

}  // namespace fluidtex
