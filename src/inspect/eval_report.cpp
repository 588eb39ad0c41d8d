#include "fluidtex/inspect/eval_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

#include <OpenImageIO/strutil.h>

#include "fluidtex/tracking/fading.h"

namespace fluidtex {

namespace {

/// Text as HTML shows it literally.
std::string html_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '&')
      out += "&amp;";
    else if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '\'')
      out += "&#39;";
    else
      out += c;
  }
  return out;
}

/// A number for people (charts, the report's table): 6 significant digits.
std::string number(double v) {
  if (std::isinf(v)) return v > 0 ? "∞" : "−∞";
  if (!std::isfinite(v)) return "–";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string png_data_uri(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  return "data:image/png;base64," + OIIO::Strutil::base64_encode(bytes.str());
}

/// The report's verdict: the figures with their grades and bounds, the
/// frame ranges where one is bad, and their worst frames.
std::string html_verdict(const Verdict& verdict, const std::vector<std::string>& worst_images) {
  std::ostringstream html;
  const char* color[] = {"#2ca02c", "#e6a100", "#d62728"};
  html << "<h2>Verdict: <span style='color:" << color[static_cast<int>(verdict.grade)] << "'>"
       << enum_name(verdict.grade) << "</span></h2><p>" << html_escape(verdict.line)
       << "</p><table><tr><th>figure</th><th>value</th><th>grade</th><th style='text-align:left'>unit</th>"
          "<th>good up to</th><th>bad above</th><th style='text-align:left'>when bad</th></tr>";
  for (const VerdictFigure& f : verdict.figures) {
    html << "<tr><th>" << f.name << "</th><td>" << number(f.value)
         << "</td><td style='color:" << (std::isnan(f.value) ? "#888" : color[static_cast<int>(f.grade)]) << "'>"
         << (std::isnan(f.value) ? "not measured" : enum_name(f.grade)) << "</td><td style='text-align:left'>"
         << html_escape(f.unit) << "</td><td>" << number(f.good) << "</td><td>" << number(f.bad)
         << "</td><td style='text-align:left'>" << html_escape(f.meaning) << "</td></tr>";
  }
  html << "</table>";
  if (!verdict.ranges.empty()) {
    html << "<h3>Where it is bad</h3><ul>";
    for (std::size_t i = 0; i < verdict.ranges.size(); ++i) {
      html << "<li>" << html_escape(verdict.ranges[i].line);
      if (i < worst_images.size())
        html << " &mdash; <a href='#worst" << i << "'>frame " << verdict.ranges[i].worst << "</a>";
      html << "</li>";
    }
    html << "</ul>";
    for (std::size_t i = 0; i < worst_images.size(); ++i) {
      html << "<figure id='worst" << i << "'><img src='" << png_data_uri(worst_images[i]) << "'><figcaption>frame "
           << verdict.ranges[i].worst << ": " << html_escape(verdict.ranges[i].line) << "</figcaption></figure>";
    }
  }
  return html.str();
}

/// The report's table of why patches leave: per rule, the patches it
/// retired by age bucket.
std::string html_retire_table(const RetiredByAge& retired) {
  std::ostringstream html;
  html << "<h2>Why patches leave</h2><p>Patches flagged to fade out or lost, by the rule that fired "
          "and their age then (frames since creation), over all frames.</p><table><tr><th>rule</th>";
  for (int b = 0; b < kAgeBuckets; ++b) {
    std::string name = age_bucket_name(b);
    std::replace(name.begin(), name.end(), '_', '-');
    html << "<th>age " << (b == kAgeBuckets - 1 ? "32+" : name) << "</th>";
  }
  html << "<th>all</th></tr>";
  for (int c = 1; c < kRetireCauses; ++c) {
    html << "<tr><th>" << to_string(static_cast<RetireCause>(c)) << "</th>";
    int total = 0;
    for (int n : retired[c]) html << "<td>" << n << "</td>", total += n;
    html << "<td>" << total << "</td></tr>";
  }
  html << "</table>";
  return html.str();
}

/// The report's charts: title, the row keys drawn, their legends.
using Chart = std::tuple<std::string, std::vector<std::string>, std::vector<std::string>>;
const std::vector<Chart>& report_charts() {
  static const std::vector<Chart> charts = {
      {"Coverage: uncovered share (should be 0)",
       {"uncovered_area", "uncovered_texels"},
       {"surface area", "chart texels"}},
      {"Ghosting: patches blended per texel", {"ghosting_mean", "ghosting_p95"}, {"mean", "95th pct"}},
      {"Patches by state",
       {"active", "fading_in", "fading_out_distorted", "fading_out_close"},
       {"active", "fading in", "out: distorted", "out: too close"}},
      {"Patch births, deaths and recuts", {"births", "deaths", "recuts"}, {"births", "deaths", "cut again in place"}},
      {"Churn: births per frame over live patches, active share",
       {"birth_rate", "active_share"},
       {"births / frame / live", "active / live"}},
      {"Patches retired per frame, by rule",
       {"retired_centre_lost", "retired_emptied", "retired_vertices_lost", "retired_split", "retired_flipped",
        "retired_quality", "retired_too_close"},
       {"centre lost", "emptied", "vertices lost", "split", "flipped", "quality", "too close"}},
      {"Patches per area where surface is destroyed, kept and made (over the first frame's)",
       {"density_sink_fast", "density_sink", "density_kept", "density_source", "density_source_fast"},
       {"shrinking > 5 %/frame", "shrinking 1-5 %", "kept (±1 %)", "growing 1-5 %", "growing > 5 %/frame"}},
      {"Births by surface change",
       {"births_sink_fast", "births_sink", "births_kept", "births_source", "births_source_fast"},
       {"shrinking > 5 %/frame", "shrinking 1-5 %", "kept (±1 %)", "growing 1-5 %", "growing > 5 %/frame"}},
      {"Removals by surface change",
       {"removals_sink_fast", "removals_sink", "removals_kept", "removals_source", "removals_source_fast"},
       {"shrinking > 5 %/frame", "shrinking 1-5 %", "kept (±1 %)", "growing 1-5 %", "growing > 5 %/frame"}},
      {"Distortion D_T", {"distortion_median", "distortion_p95"}, {"median", "95th pct"}},
      {"Warping error (σ units)", {"warp_advected", "warp_fixed", "warp_random"}, {"advected", "not moving", "random"}},
      {"Optical flow vs projected velocity (px)",
       {"flow_endpoint_px", "flow_speed_px", "flow_slow_endpoint_px", "flow_slow_speed_px"},
       {"endpoint error", "|velocity| (static)", "endpoint error, slow pixels", "|velocity|, slow pixels"}},
      {"Optical flow angular error (deg)", {"flow_angular_deg"}, {"angular"}},
      {"Contrast σ_out / σ_exemplar", {"contrast_r", "contrast_g", "contrast_b", "contrast"}, {"R", "G", "B", "grey"}},
      {"Spectrum distance to the exemplar", {"spectrum_distance"}, {"log-spectrum RMS"}},
      {"Orientation: structure-tensor coherence",
       {"orientation_coherence", "orientation_coherence_exemplar", "orientation_coherence_ratio"},
       {"atlas", "exemplar", "ratio"}},
      {"Orientation against the exemplar",
       {"orientation_histogram_distance", "orientation_histogram_distance_aligned"},
       {"directions as drawn", "up to a turn"}},
      {"Dominant direction against the exemplar's (deg)", {"orientation_angle_deg"}, {"angle"}},
      {"Nearest-window energy over the exemplar's own", {"window_energy_ratio"}, {"ratio"}},
      {"Colour histogram distance (exemplar σ)", {"histogram_distance"}, {"Wasserstein"}},
      {"Exemplar tile on the surface (scene units)",
       {"exemplar_size", "exemplar_size_measured"},
       {"the job's", "measured on the atlas"}},
  };
  return charts;
}

}  // namespace

std::string svg_chart(const std::string& title, const std::vector<MetricRow>& rows,
                      const std::vector<std::string>& keys, const std::vector<std::string>& labels) {
  const double W = 560, H = 230, L = 56, R = 150, T = 24, B = 34;
  double x0 = 1e300, x1 = -1e300, y0 = 0.0, y1 = -1e300;
  for (const MetricRow& r : rows) {
    const double f = metric_value(r, "frame");
    for (const std::string& k : keys) {
      const double v = metric_value(r, k);
      if (!std::isfinite(v)) continue;
      x0 = std::min(x0, f), x1 = std::max(x1, f);
      y0 = std::min(y0, v), y1 = std::max(y1, v);
    }
  }
  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << W << "' height='" << H
    << "' font-family='sans-serif' font-size='11'>";
  s << "<text x='" << L << "' y='14' font-weight='bold'>" << title << "</text>";
  if (!(x1 >= x0) || !(y1 > -1e300)) return s.str() + "<text x='60' y='100'>not measured</text></svg>";
  if (x1 == x0) x1 = x0 + 1;
  if (y1 <= y0) y1 = y0 + (y0 == 0.0 ? 1.0 : std::abs(y0) * 0.1);  // a flat series: a readable axis
  auto X = [&](double f) { return L + (f - x0) / (x1 - x0) * (W - L - R); };
  auto Y = [&](double v) { return H - B - (v - y0) / (y1 - y0) * (H - T - B); };
  s << "<rect x='" << L << "' y='" << T << "' width='" << W - L - R << "' height='" << H - T - B
    << "' fill='none' stroke='#999'/>";
  // Ticks at 1, 2 or 5 times a power of ten, about five on each axis, with
  // grid lines across the plot.
  auto step_for = [](double range) {
    const double raw = range / 5.0, power = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0})
      if (m * power >= raw) return m * power;
    return 10.0 * power;
  };
  const double ystep = step_for(y1 - y0), xstep = std::max(1.0, step_for(x1 - x0));
  for (double v = std::ceil(y0 / ystep) * ystep; v <= y1 + 1e-9 * ystep; v += ystep) {
    const double y = Y(v);
    s << "<line x1='" << L << "' x2='" << W - R << "' y1='" << y << "' y2='" << y << "' stroke='#e4e4e4'/>";
    s << "<text x='" << L - 4 << "' y='" << y + 4 << "' text-anchor='end'>" << number(std::abs(v) < 1e-12 ? 0.0 : v)
      << "</text>";
  }
  for (double f = std::ceil(x0 / xstep) * xstep; f <= x1 + 1e-9; f += xstep) {
    s << "<line x1='" << X(f) << "' x2='" << X(f) << "' y1='" << H - B << "' y2='" << H - B + 4
      << "' stroke='#999'/><text x='" << X(f) << "' y='" << H - B + 15 << "' text-anchor='middle'>" << number(f)
      << "</text>";
  }
  s << "<text x='" << W - R << "' y='" << H - 2 << "' text-anchor='end'>frame</text>";
  const char* colors[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2"};
  for (std::size_t k = 0; k < keys.size(); ++k) {
    std::string path;
    for (const MetricRow& r : rows) {
      const double v = metric_value(r, keys[k]);
      if (!std::isfinite(v)) continue;
      char buf[64];
      std::snprintf(buf, sizeof buf, "%s%.1f,%.1f", path.empty() ? "M" : " L", X(metric_value(r, "frame")), Y(v));
      path += buf;
    }
    const char* color = colors[k % 7];
    s << "<path d='" << path << "' fill='none' stroke='" << color << "' stroke-width='1.5'/>";
    s << "<text x='" << W - R + 8 << "' y='" << T + 12 + 14 * k << "' fill='" << color << "'>" << labels[k]
      << "</text>";
  }
  return s.str() + "</svg>";
}

std::string html_report(const EvalReport& report) {
  const std::string& run_dir = report.run_dir;
  std::ostringstream html;
  html << "<!DOCTYPE html><html><head><meta charset='utf-8'><title>fluidtex eval: " << run_dir
       << "</title><style>body{font-family:sans-serif;margin:24px;max-width:1200px}td,th{padding:2px "
          "10px;text-align:right}"
          "th{text-align:left}figure{display:inline-block;margin:6px}img{max-width:280px}</style></head><body>";
  html << "<h1>fluidtex eval</h1><p>Run: <code>" << run_dir << "</code>, " << report.rows.size()
       << " frames. Warping error is the mean colour change along the flow between consecutive frames in units of the "
          "exemplar's σ; a texture that moves with the fluid stays far below both baselines (a texture that does not "
          "move, and random points).</p>";
  html << html_verdict(report.verdict, report.worst_images);
  html << "<h2>Summary</h2><p>Means over the frames measured (metrics.jsonl has every frame).</p><table>";
  for (const auto& [k, v] : report.summary) html << "<tr><th>" << k << "</th><td>" << number(v) << "</td></tr>";
  html << "</table>" << html_retire_table(report.retired);
  html << "<h2>Per frame</h2>";
  for (const auto& [title, ks, labels] : report_charts()) html << svg_chart(title, report.rows, ks, labels) << "\n";
  if (!report.gallery.empty()) {
    html << "<h2>Texture against the exemplar</h2><p>The exemplar resampled where it lands on the surface, beside "
            "views of the atlas of the same size as the surface shows them (turned back along the flow map's "
            "projection axes), of the first, middle and last frames.</p>";
    for (const auto& [png, caption] : report.gallery) {
      html << "<figure><img src='" << png_data_uri(png) << "'><figcaption>" << html_escape(caption)
           << "</figcaption></figure>";
    }
  }
  html << "<h2>Frames</h2>";
  for (const std::string& png : report.images) {
    html << "<figure><img src='" << png_data_uri(png) << "'><figcaption>"
         << std::filesystem::path(png).filename().string() << "</figcaption></figure>";
  }
  html << "</body></html>\n";
  return html.str();
}

}  // namespace fluidtex
