// The verdict's appearance figures on hand-made per-frame rows: which
// frames are bad, what the shot's value is, and when a figure is not
// judged.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "fluidtex/inspect/verdict.h"

namespace fluidtex {
namespace {

const VerdictFigure& figure(const Verdict& v, const std::string& key) {
  for (const VerdictFigure& f : v.figures) {
    if (f.key == key) return f;
  }
  ADD_FAILURE() << "no figure " << key;
  return v.figures.front();
}

/// Frames 1..n with an oriented exemplar (coherence `exemplar`), the atlas
/// at `ratio` of it, and the window energy and colour distance given.
std::vector<MetricRow> rows(int n, double exemplar, double ratio, double energy, double histogram) {
  std::vector<MetricRow> out;
  for (int f = 1; f <= n; ++f) {
    out.push_back({{"frame", f},
                   {"orientation_coherence_exemplar", exemplar},
                   {"orientation_coherence_ratio", ratio},
                   {"window_energy_ratio", energy},
                   {"histogram_distance", histogram}});
  }
  return out;
}

void set(MetricRow& row, const std::string& key, double value) {
  for (auto& [k, v] : row) {
    if (k == key) v = value;
  }
}

TEST(Verdict, AppearanceFiguresAreGoodForTheExemplarsOwnLook) {
  const Verdict v = judge(rows(4, 0.5, 1.05, 0.9, 0.03), EvalThresholds{});
  EXPECT_EQ(v.grade, Grade::Good) << v.line;
  EXPECT_NEAR(figure(v, "orientation").value, 0.05, 1e-12);
  EXPECT_NEAR(figure(v, "structure").value, 0.9, 1e-12);
  EXPECT_NEAR(figure(v, "colours").value, 0.03, 1e-12);
}

TEST(Verdict, MixedDirectionsAreBadOnAnOrientedExemplarOnly) {
  // Patches turned every way halve the coherence of a wood grain: bad.
  const Verdict wood = judge(rows(4, 0.5, 0.5, 1.0, 0.03), EvalThresholds{});
  EXPECT_EQ(figure(wood, "orientation").grade, Grade::Bad);
  EXPECT_NE(wood.line.find("directionality change 0.5"), std::string::npos) << wood.line;
  // On an isotropic exemplar the ratio is noise: not judged.
  const Verdict noise = judge(rows(4, 0.05, 0.5, 1.0, 0.03), EvalThresholds{});
  EXPECT_TRUE(std::isnan(figure(noise, "orientation").value));
  EXPECT_EQ(noise.grade, Grade::Good) << noise.line;
}

TEST(Verdict, WindowEnergyAndColoursAreJudgedPerFrameRange) {
  std::vector<MetricRow> r = rows(6, 0.5, 1.0, 1.0, 0.03);
  for (int f : {3, 4}) {
    set(r[f - 1], "window_energy_ratio", 3.2);  // overlaid copies on frames 3-4
    set(r[f - 1], "histogram_distance", 0.4);
  }
  const Verdict v = judge(r, EvalThresholds{});
  EXPECT_EQ(figure(v, "structure").grade, Grade::Warn);  // the shot's mean, 1.73
  bool structure = false, colours = false;
  for (const VerdictRange& range : v.ranges) {
    structure |= range.key == "structure" && range.first == 3 && range.last == 4;
    colours |= range.key == "colours" && range.first == 3 && range.last == 4;
  }
  EXPECT_TRUE(structure && colours) << verdict_json(v);
  // The bounds are options.
  EvalThresholds loose;
  loose.window_energy_good = 2.0;
  loose.window_energy_bad = 4.0;
  loose.histogram_bad = 0.5;
  EXPECT_TRUE(judge(r, loose).ranges.empty()) << verdict_json(judge(r, loose));
}

}  // namespace
}  // namespace fluidtex
