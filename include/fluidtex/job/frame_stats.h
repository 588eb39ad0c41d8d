/// @file frame_stats.h
/// @brief `stats.jsonl`: one JSON object per frame, appended as each frame
/// completes (the file is rewritten atomically each time, so a crash never
/// leaves a torn line).
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "fluidtex/tracking/patch_counts.h"
#include "fluidtex/util/timing.h"

namespace fluidtex {

struct FrameStats {
  int frame = 0;
  std::string method;  ///< texturing method ("patches", "flowmap"); omitted when empty
  std::size_t vertices = 0;
  std::size_t faces = 0;
  PatchCounts patches;
  /// Stage name -> wall seconds, written in insertion order.
  StageSeconds seconds;
  double uncovered_fraction = 0.0;
  /// Further numbers (e.g. "packing_efficiency", "texels_per_second").
  std::vector<std::pair<std::string, double>> extra;
};

/// One JSON object on one line (no trailing newline), keys in order: frame,
/// method (when set), vertices, faces, patches{...}, seconds{... insertion order},
/// uncovered_fraction, then the extra keys. Numbers are locale-independent,
/// shortest round-trip (std::to_chars); non-finite numbers are written as
/// null; keys are JSON-escaped.
std::string to_json_line(const FrameStats& stats);

/// Accumulates lines and keeps `path` up to date.
class StatsWriter {
 public:
  /// Without `append_existing` the file is (atomically) emptied at once, so a
  /// new run never leaves an earlier run's lines behind. With it (--resume),
  /// the existing file's lines are loaded and kept (a missing file is fine;
  /// an unreadable one is an InputError).
  explicit StatsWriter(std::string path, bool append_existing = false);
  /// Appends the frame's line (replacing an earlier line of the same frame,
  /// e.g. a frame redone after a resume) and rewrites the file atomically.
  void add(const FrameStats& stats);
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::vector<std::string> lines_;
};

}  // namespace fluidtex
