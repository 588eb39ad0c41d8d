#include "fluidtex/inspect/verdict.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "fluidtex/util/error.h"
#include "fluidtex/util/json.h"

namespace fluidtex {

namespace {

/// How a shot's value comes from its frames.
enum class Aggregate {
  Largest,         ///< the largest frame's value
  Mean,            ///< the mean of the frames' values
  MeanAfterFirst,  ///< the same without the first frame (whose disks are all new)
  SummedRatio,     ///< Σ column / Σ denominator over the frames
  MeanFromOne,     ///< |mean of column − 1|
};

/// A headline figure: what it is called and means, how one frame's value is
/// read from its row and the shot's from the frames, whether runs of bad
/// frames are reported, and its bounds.
struct Measure {
  const char* key;
  const char* name;
  const char* unit;
  const char* meaning;
  double (*per_frame)(const MetricRow&);
  Aggregate how;
  bool ranges;  ///< report the frame ranges where it is bad
  double EvalThresholds::*good;
  double EvalThresholds::*bad;
  const char* column = "";       ///< SummedRatio, MeanFromOne: the column summed
  const char* denominator = "";  ///< SummedRatio
};

/// A frame's warping ratio; infinite for a texture that does not change in
/// place at all (a still texture) while it changes along the liquid.
double warping(const MetricRow& r) {
  const double fixed = metric_value(r, "warp_fixed"), advected = metric_value(r, "warp_advected");
  if (fixed > 0.0) return advected / fixed;
  return advected > 0.0 ? std::numeric_limits<double>::infinity() : std::numeric_limits<double>::quiet_NaN();
}

/// A frame's flow error over its slow pixels; not judged where they move
/// less than a pixel a frame (the ratio is noise there).
double flow(const MetricRow& r) {
  const double speed = metric_value(r, "flow_slow_speed_px");
  return speed >= 1.0 ? metric_value(r, "flow_slow_endpoint_px") / speed : std::numeric_limits<double>::quiet_NaN();
}

/// An exemplar's windows of one tile are directional from this coherence
/// of their structure tensor on (wood 0.5, bricks and lit stones 0.2 to
/// 0.35; noise, spots and bubbles 0.02 to 0.09): below it the coherence
/// ratio is a ratio of noise and is not judged.
constexpr double kDirectionalCoherence = 0.1;

/// A frame's directionality change |coherence ratio − 1|, on exemplars
/// with a direction.
double orientation_change(const MetricRow& r) {
  if (!(metric_value(r, "orientation_coherence_exemplar") >= kDirectionalCoherence))
    return std::numeric_limits<double>::quiet_NaN();
  return std::abs(metric_value(r, "orientation_coherence_ratio") - 1.0);
}

using T = EvalThresholds;
const Measure kMeasures[] = {
    {"coverage", "uncovered surface", "share of the surface area, largest frame", "the texture leaves surface bare",
     [](const MetricRow& r) { return metric_value(r, "uncovered_area"); }, Aggregate::Largest, true, &T::uncovered_good,
     &T::uncovered_bad},
    {"warping", "warping ratio", "change along the liquid's motion over a still texture's change in place (0 to 1+)",
     "the texture slides against the liquid", warping, Aggregate::Mean, true, &T::warping_good, &T::warping_bad},
    {"flow", "flow error", "optical-flow endpoint error over the liquid's projected motion, pixels under 15 px",
     "the texture's motion disagrees with the liquid's", flow, Aggregate::SummedRatio, true, &T::flow_good,
     &T::flow_bad, "flow_slow_endpoint_px", "flow_slow_speed_px"},
    {"ghosting", "ghosting", "patches blended per texel, mean", "many patches blend into a blur",
     [](const MetricRow& r) { return metric_value(r, "ghosting_mean"); }, Aggregate::Mean, true, &T::ghosting_good,
     &T::ghosting_bad},
    {"contrast", "contrast change", "|σ of the atlas's green over the exemplar's − 1|",
     "the texture is washed out, or harsher than its exemplar",
     [](const MetricRow& r) { return std::abs(metric_value(r, "contrast_g") - 1.0); }, Aggregate::MeanFromOne, false,
     &T::contrast_good, &T::contrast_bad, "contrast_g"},
    {"orientation", "directionality change",
     "|structure-tensor coherence of the atlas over the exemplar's − 1|, exemplars with a direction (coherence ≥ "
     "0.1)",
     "patches show the exemplar's direction at different angles: a pattern reads as a heap", orientation_change,
     Aggregate::Mean, false, &T::orientation_good, &T::orientation_bad},
    {"structure", "window energy",
     "distance of atlas windows to the nearest exemplar window at any turn, over the exemplar's own (1 = as the "
     "exemplar)",
     "the texture shows structure its exemplar does not have (overlaid copies, seams, smears)",
     [](const MetricRow& r) { return metric_value(r, "window_energy_ratio"); }, Aggregate::Mean, true,
     &T::window_energy_good, &T::window_energy_bad},
    {"colours", "colour histogram distance",
     "Wasserstein distance of the chart texels' values to the exemplar's at the atlas's scale, in exemplar σ",
     "the colours or their spread differ from the exemplar's",
     [](const MetricRow& r) { return metric_value(r, "histogram_distance"); }, Aggregate::Mean, true,
     &T::histogram_good, &T::histogram_bad},
    {"churn", "churn", "births per live patch a frame", "patches are born and fade all the time (popping)",
     [](const MetricRow& r) { return metric_value(r, "birth_rate"); }, Aggregate::MeanAfterFirst, false, &T::churn_good,
     &T::churn_bad},
    {"distortion", "distortion", "95th percentile of the patch triangles' D_T (1 = undistorted)",
     "the texture is stretched or squeezed", [](const MetricRow& r) { return metric_value(r, "distortion_p95"); },
     Aggregate::Mean, false, &T::distortion_good, &T::distortion_bad},
};

Grade grade_of(double value, double good, double bad) {
  if (std::isnan(value) || value <= good) return Grade::Good;
  return value > bad ? Grade::Bad : Grade::Warn;
}

/// The shot's value of `m` (Aggregate); NaN when no frame has it.
double shot_value(const Measure& m, const std::vector<MetricRow>& rows) {
  const double none = std::numeric_limits<double>::quiet_NaN();
  double sum = 0.0, other = 0.0, largest = -std::numeric_limits<double>::infinity();
  int n = 0;
  for (std::size_t i = m.how == Aggregate::MeanAfterFirst ? 1 : 0; i < rows.size(); ++i) {
    if (m.how == Aggregate::SummedRatio || m.how == Aggregate::MeanFromOne) {
      const double c = metric_value(rows[i], m.column);
      const double d = m.how == Aggregate::SummedRatio ? metric_value(rows[i], m.denominator) : 1.0;
      if (std::isfinite(c) && std::isfinite(d)) sum += c, other += d, ++n;
      continue;
    }
    const double v = m.per_frame(rows[i]);
    if (!std::isnan(v)) sum += v, ++n, largest = std::max(largest, v);
  }
  if (n == 0) return none;
  switch (m.how) {
    case Aggregate::Largest: return largest;
    case Aggregate::SummedRatio: return other > 0.0 ? sum / other : none;
    case Aggregate::MeanFromOne: return std::abs(sum / n - 1.0);
    default: return sum / n;
  }
}

std::string figure_text(double v) {
  if (std::isinf(v)) return "∞";
  char buf[32];
  std::snprintf(buf, sizeof buf, std::abs(v) < 0.01 && v != 0.0 ? "%.2g" : "%.3g", v);
  return buf;
}

std::string range_text(int first, int last) {
  return first == last ? "frame " + std::to_string(first)
                       : "frames " + std::to_string(first) + "–" + std::to_string(last);
}

}  // namespace

void EvalThresholds::validate() const {
  check_options(*this);
  for (const ThresholdOption& t : kThresholdOptions) {
    if (this->*t.good > this->*t.bad)
      throw InputError("", "--" + std::string(t.good_name) + " " + format_number(this->*t.good) + " is above --" +
                               t.bad_name + " " + format_number(this->*t.bad));
  }
}

std::vector<OptionRef> option_table(EvalThresholds& t) {
  std::vector<OptionRef> table;
  EvalThresholds::for_each_option(
      t, [&](const OptionInfo& info, auto& field) { table.push_back(bind_option(info, field)); });
  return table;
}

Verdict judge(const std::vector<MetricRow>& rows, const EvalThresholds& thresholds) {
  Verdict verdict;
  for (const Measure& m : kMeasures) {
    VerdictFigure f;
    f.key = m.key, f.name = m.name, f.unit = m.unit, f.meaning = m.meaning;
    f.good = thresholds.*m.good, f.bad = thresholds.*m.bad;
    f.value = shot_value(m, rows);
    f.grade = grade_of(f.value, f.good, f.bad);
    verdict.grade = std::max(verdict.grade, f.grade);
    verdict.figures.push_back(f);
    // Runs of consecutive frames where this figure is bad.
    if (!m.ranges) continue;  // judged over the shot only
    VerdictRange open;
    bool in_range = false;
    auto close = [&] {
      if (!in_range) return;
      open.key = f.key;
      open.line = range_text(open.first, open.last) + ": " + f.meaning + " (" + f.name + " up to " +
                  figure_text(open.worst_value) + ")";
      verdict.ranges.push_back(open);
      in_range = false;
    };
    for (const MetricRow& r : rows) {
      const double v = m.per_frame(r);
      const int frame = static_cast<int>(metric_value(r, "frame"));
      if (grade_of(v, f.good, f.bad) != Grade::Bad) {
        close();
        continue;
      }
      if (!in_range) open = VerdictRange{frame, frame, frame, f.key, v, ""}, in_range = true;
      open.last = frame;
      if (v > open.worst_value) open.worst_value = v, open.worst = frame;
    }
    close();
  }
  // The line: the worst figures, bad before warn.
  std::string worst;
  for (Grade g : {Grade::Bad, Grade::Warn}) {
    for (const VerdictFigure& f : verdict.figures) {
      if (f.grade != g) continue;
      if (!worst.empty()) worst += "; ";
      worst += f.name + " " + figure_text(f.value) + " (" +
               (g == Grade::Bad ? "bad above " + figure_text(f.bad) : "good up to " + figure_text(f.good)) +
               "): " + f.meaning;
    }
    if (!worst.empty()) break;
  }
  verdict.line = std::string(enum_name(verdict.grade)) + ": " + (worst.empty() ? "every figure is good" : worst);
  return verdict;
}

std::string verdict_json(const Verdict& verdict) {
  std::ostringstream s;
  auto number = [](double v) { return std::isfinite(v) ? format_number(v) : std::string("null"); };
  s << "{\"grade\":\"" << enum_name(verdict.grade) << "\",\"line\":" << json_string(verdict.line) << ",\"figures\":[";
  for (std::size_t i = 0; i < verdict.figures.size(); ++i) {
    const VerdictFigure& f = verdict.figures[i];
    s << (i ? "," : "") << "{\"key\":\"" << f.key << "\",\"name\":" << json_string(f.name)
      << ",\"value\":" << number(f.value) << ",\"unit\":" << json_string(f.unit) << ",\"good\":" << number(f.good)
      << ",\"bad\":" << number(f.bad) << ",\"grade\":\"" << enum_name(f.grade)
      << "\",\"meaning\":" << json_string(f.meaning) << "}";
  }
  s << "],\"frames\":[";
  for (std::size_t i = 0; i < verdict.ranges.size(); ++i) {
    const VerdictRange& r = verdict.ranges[i];
    s << (i ? "," : "") << "{\"first\":" << r.first << ",\"last\":" << r.last << ",\"worst\":" << r.worst
      << ",\"key\":\"" << r.key << "\",\"line\":" << json_string(r.line) << "}";
  }
  s << "]}\n";
  return s.str();
}

}  // namespace fluidtex
