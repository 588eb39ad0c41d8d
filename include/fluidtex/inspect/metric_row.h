/// @file metric_row.h
/// @brief One frame's figures in `fluidtex eval` (a line of
/// OUT/eval/metrics.jsonl), or the summary's means, by name.
#pragma once

#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace fluidtex {

/// eval's per-frame figures (and the summary's means) by name, in the order
/// they were measured; NaN = not measured.
using MetricRow = std::vector<std::pair<std::string, double>>;

/// The figure `key` of `row`; NaN when the row does not have it.
inline double metric_value(const MetricRow& row, const std::string& key) {
  for (const auto& [k, v] : row) {
    if (k == key) return v;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace fluidtex
