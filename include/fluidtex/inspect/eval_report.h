/// @file eval_report.h
/// @brief `eval`'s self-contained HTML report (OUT/eval/report.html): the
/// verdict with the worst frames, the summary, why patches leave, one
/// chart per figure against frame, the exemplar at the surface's scale
/// beside crops of the atlas, and preview renders, with every image
/// inline so that the page can be mailed or attached to a ticket.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "fluidtex/inspect/metric_row.h"
#include "fluidtex/inspect/patch_history.h"
#include "fluidtex/inspect/verdict.h"

namespace fluidtex {

/// What the report shows.
struct EvalReport {
  std::string run_dir;                    ///< the run's folder (the page's title)
  std::vector<MetricRow> rows;            ///< per frame, as in metrics.jsonl
  MetricRow summary;                      ///< as in summary.json
  RetiredByAge retired{};                 ///< the removal table
  Verdict verdict;                        ///< as in verdict.json
  std::vector<std::string> worst_images;  ///< a PNG per verdict range (the first ones), in order
  std::vector<std::string> images;        ///< preview PNGs
  /// (PNG, caption): the exemplar at the surface's scale, then atlas crops
  /// of the same size (the first, middle and last frames).
  std::vector<std::pair<std::string, std::string>> gallery;
};

/// The report as one HTML page (PNGs read and embedded as data URIs).
std::string html_report(const EvalReport& report);

/// One figure (or several, `keys` with their `labels`) of `rows` against
/// their "frame" as an inline SVG line chart; "not measured" when no row
/// has a finite value.
std::string svg_chart(const std::string& title, const std::vector<MetricRow>& rows,
                      const std::vector<std::string>& keys, const std::vector<std::string>& labels);

}  // namespace fluidtex
