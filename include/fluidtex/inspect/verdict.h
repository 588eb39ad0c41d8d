/// @file verdict.h
/// @brief Whether a shot is good: `fluidtex eval`'s headline figures, each
/// with its unit, what it means and good / warn / bad thresholds, one line
/// per shot and one per range of frames where a figure is bad. What
/// `eval --check` gates a pipeline on.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "fluidtex/inspect/metric_row.h"
#include "fluidtex/util/enum_names.h"
#include "fluidtex/util/options.h"

namespace fluidtex {

enum class Grade { Good, Warn, Bad };
inline constexpr EnumName<Grade> kGradeNames[] = {{Grade::Good, "good"}, {Grade::Warn, "warn"}, {Grade::Bad, "bad"}};
constexpr const auto& enum_names(Grade) { return kGradeNames; }

/// Where a figure turns from good to warn and from warn to bad: a value
/// above `good` warns, above `bad` is bad (for the contrast: its distance
/// from 1). Set on eval's command line or in the `[eval]` table of a
/// `--thresholds` file.
struct EvalThresholds {
  double uncovered_good = 0.0, uncovered_bad = 1e-4;
  double warping_good = 0.5, warping_bad = 0.8;
  double flow_good = 0.3, flow_bad = 0.6;
  double ghosting_good = 2.5, ghosting_bad = 4.0;
  double contrast_good = 0.1, contrast_bad = 0.25;
  double orientation_good = 0.2, orientation_bad = 0.35;
  double window_energy_good = 1.5, window_energy_bad = 2.5;
  double histogram_good = 0.1, histogram_bad = 0.25;
  double churn_good = 0.05, churn_bad = 0.1;
  double distortion_good = 3.5, distortion_bad = 5.0;

  template <class Self, class F>
  static void for_each_option(Self& o, F&& f);
  /// InputError for a bound out of range or a good threshold above its bad one.
  void validate() const;
};

/// One figure's two bounds as options: NAME-good and NAME-bad.
struct ThresholdOption {
  const char* good_name;
  const char* good_help;
  const char* bad_name;
  const char* bad_help;
  Bounds bounds;
  double EvalThresholds::*good;
  double EvalThresholds::*bad;
};

inline constexpr ThresholdOption kThresholdOptions[] = {
    {"uncovered-good", "Bare surface share that still counts as good", "uncovered-bad",
     "Bare surface share above which a shot is bad", between(0, 1), &EvalThresholds::uncovered_good,
     &EvalThresholds::uncovered_bad},
    {"warping-good", "Warping ratio up to which a shot is good", "warping-bad",
     "Warping ratio above which a shot is bad", at_least(0), &EvalThresholds::warping_good,
     &EvalThresholds::warping_bad},
    {"flow-good", "Flow error up to which a shot is good", "flow-bad", "Flow error above which a shot is bad",
     at_least(0), &EvalThresholds::flow_good, &EvalThresholds::flow_bad},
    {"ghosting-good", "Patches blended per texel up to which a shot is good", "ghosting-bad",
     "Patches blended per texel above which a shot is bad", at_least(0), &EvalThresholds::ghosting_good,
     &EvalThresholds::ghosting_bad},
    {"contrast-good", "Contrast change |σ ratio − 1| up to which a shot is good", "contrast-bad",
     "Contrast change |σ ratio − 1| above which a shot is bad", at_least(0), &EvalThresholds::contrast_good,
     &EvalThresholds::contrast_bad},
    {"orientation-good", "Directionality change |coherence ratio − 1| up to which a shot is good", "orientation-bad",
     "Directionality change |coherence ratio − 1| above which a shot is bad", at_least(0),
     &EvalThresholds::orientation_good, &EvalThresholds::orientation_bad},
    {"window-energy-good", "Nearest-window energy ratio up to which a shot is good", "window-energy-bad",
     "Nearest-window energy ratio above which a shot is bad", at_least(0), &EvalThresholds::window_energy_good,
     &EvalThresholds::window_energy_bad},
    {"histogram-good", "Colour histogram distance (exemplar σ) up to which a shot is good", "histogram-bad",
     "Colour histogram distance (exemplar σ) above which a shot is bad", at_least(0), &EvalThresholds::histogram_good,
     &EvalThresholds::histogram_bad},
    {"churn-good", "Births per live patch a frame up to which a shot is good", "churn-bad",
     "Births per live patch a frame above which a shot is bad", at_least(0), &EvalThresholds::churn_good,
     &EvalThresholds::churn_bad},
    {"distortion-good", "95th percentile of D_T up to which a shot is good", "distortion-bad",
     "95th percentile of D_T above which a shot is bad", at_least(0), &EvalThresholds::distortion_good,
     &EvalThresholds::distortion_bad},
};

template <class Self, class F>
void EvalThresholds::for_each_option(Self& o, F&& f) {
  for (const ThresholdOption& t : kThresholdOptions) {
    f(OptionInfo{.name = t.good_name, .help = t.good_help, .bounds = t.bounds, .group = "Verdict thresholds"},
      o.*t.good);
    f(OptionInfo{.name = t.bad_name, .help = t.bad_help, .bounds = t.bounds, .group = "Verdict thresholds"}, o.*t.bad);
  }
}

/// The option table of `t` (command line and `--thresholds` files).
std::vector<OptionRef> option_table(EvalThresholds& t);

/// One headline figure of a shot.
struct VerdictFigure {
  std::string key;      ///< verdict.json's name: coverage, warping, flow, ghosting, contrast, orientation,
                        ///< structure, colours, churn, distortion
  std::string name;     ///< for people: "warping ratio"
  std::string unit;     ///< "share of the surface area", "× a still texture's change", ...
  std::string meaning;  ///< what a bad value looks like on screen
  double value = 0.0;   ///< NaN: not measured in this run
  double good = 0.0, bad = 0.0;
  Grade grade = Grade::Good;
};

/// A range of frames where one figure is bad, and its worst frame.
struct VerdictRange {
  int first = 0, last = 0, worst = 0;
  std::string key;
  double worst_value = 0.0;
  std::string line;  ///< "frames 13–17: the texture slides against the liquid (warping ratio up to 0.93)"
};

struct Verdict {
  Grade grade = Grade::Good;  ///< the worst figure's
  std::string line;           ///< "bad: warping ratio 0.93 (bad above 0.8): the texture slides against the liquid"
  std::vector<VerdictFigure> figures;
  std::vector<VerdictRange> ranges;
};

/// The verdict on a shot from eval's per-frame rows (each with "frame").
Verdict judge(const std::vector<MetricRow>& rows, const EvalThresholds& thresholds);

/// verdict.json: the grade, the line, the figures and the frame ranges.
std::string verdict_json(const Verdict& verdict);

}  // namespace fluidtex
