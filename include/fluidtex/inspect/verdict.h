/// @file verdict.h
/// @brief Whether a shot is good: `fluidtex eval`'s headline figures, each
/// with its unit, what it means and good / warn / bad thresholds, one line
/// per shot and one per range of frames where a figure is bad. What
/// `eval --check` gates a pipeline on.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "fluidtex/util/enum_names.h"
#include "fluidtex/util/options.h"

namespace fluidtex {

/// eval's per-frame figures (and the summary's means) by name; NaN = not
/// measured.
using MetricRow = std::vector<std::pair<std::string, double>>;

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
  double churn_good = 0.05, churn_bad = 0.1;
  double distortion_good = 3.5, distortion_bad = 5.0;

  template <class Self, class F>
  static void for_each_option(Self& o, F&& f) {
    const Bounds share = between(0, 1), positive = at_least(0);
    const char* g = "Verdict thresholds";
    f(OptionInfo{.name = "uncovered-good",
                 .help = "Bare surface share that still counts as good",
                 .bounds = share,
                 .group = g},
      o.uncovered_good);
    f(OptionInfo{.name = "uncovered-bad",
                 .help = "Bare surface share above which a shot is bad",
                 .bounds = share,
                 .group = g},
      o.uncovered_bad);
    f(
        OptionInfo{
            .name = "warping-good", .help = "Warping ratio up to which a shot is good", .bounds = positive, .group = g},
        o.warping_good);
    f(
        OptionInfo{
            .name = "warping-bad", .help = "Warping ratio above which a shot is bad", .bounds = positive, .group = g},
        o.warping_bad);
    f(OptionInfo{.name = "flow-good", .help = "Flow error up to which a shot is good", .bounds = positive, .group = g},
      o.flow_good);
    f(OptionInfo{.name = "flow-bad", .help = "Flow error above which a shot is bad", .bounds = positive, .group = g},
      o.flow_bad);
    f(OptionInfo{.name = "ghosting-good",
                 .help = "Patches blended per texel up to which a shot is good",
                 .bounds = positive,
                 .group = g},
      o.ghosting_good);
    f(OptionInfo{.name = "ghosting-bad",
                 .help = "Patches blended per texel above which a shot is bad",
                 .bounds = positive,
                 .group = g},
      o.ghosting_bad);
    f(OptionInfo{.name = "contrast-good",
                 .help = "Contrast change |σ ratio − 1| up to which a shot is good",
                 .bounds = positive,
                 .group = g},
      o.contrast_good);
    f(OptionInfo{.name = "contrast-bad",
                 .help = "Contrast change |σ ratio − 1| above which a shot is bad",
                 .bounds = positive,
                 .group = g},
      o.contrast_bad);
    f(OptionInfo{.name = "churn-good",
                 .help = "Births per live patch a frame up to which a shot is good",
                 .bounds = positive,
                 .group = g},
      o.churn_good);
    f(OptionInfo{.name = "churn-bad",
                 .help = "Births per live patch a frame above which a shot is bad",
                 .bounds = positive,
                 .group = g},
      o.churn_bad);
    f(OptionInfo{.name = "distortion-good",
                 .help = "95th percentile of D_T up to which a shot is good",
                 .bounds = positive,
                 .group = g},
      o.distortion_good);
    f(OptionInfo{.name = "distortion-bad",
                 .help = "95th percentile of D_T above which a shot is bad",
                 .bounds = positive,
                 .group = g},
      o.distortion_bad);
  }
  /// InputError for a bound out of range or a good threshold above its bad one.
  void validate() const;
};

/// The option table of `t` (command line and `--thresholds` files).
std::vector<OptionRef> option_table(EvalThresholds& t);

/// One headline figure of a shot.
struct VerdictFigure {
  std::string key;      ///< verdict.json's name: coverage, warping, flow, ghosting, contrast, churn, distortion
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
