/// @file stats.h
/// @brief `stats.jsonl`: one JSON object per frame, appended as each frame
/// completes (the file is rewritten atomically each time, so a crash never
/// leaves a torn line).
#pragma once

#include <map>
#include <string>
#include <vector>

namespace fluidtex {

struct PatchCounts {
  int fading_in = 0;
  int active = 0;
  int fading_out_distorted = 0;
  int fading_out_close = 0;
  int total() const { return fading_in + active + fading_out_distorted + fading_out_close; }
};

struct FrameStats {
  int frame = 0;
  std::size_t vertices = 0;
  std::size_t faces = 0;
  PatchCounts patches;
  /// Stage name -> wall seconds, written in insertion order.
  std::vector<std::pair<std::string, double>> seconds;
  double uncovered_fraction = 0.0;
  /// Further numbers (e.g. "packing_efficiency", "texels_per_second").
  std::vector<std::pair<std::string, double>> extra;
};

/// One JSON object on one line (no trailing newline). Non-finite numbers are
/// written as null.
std::string to_json_line(const FrameStats& stats);

/// Accumulates lines and keeps `path` up to date.
class StatsWriter {
 public:
  explicit StatsWriter(std::string path, bool append_existing = false);
  void add(const FrameStats& stats);  ///< appends and rewrites the file atomically
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::vector<std::string> lines_;
};

}  // namespace fluidtex
