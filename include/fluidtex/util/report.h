/// @file report.h
/// @brief How library stages talk to the user without owning a terminal: the
/// application passes a Reporter; the library calls it. Repeated warnings are
/// the caller's to batch (stages count per-patch failures and report once).
#pragma once

#include <string>

namespace fluidtex {

/// A frame whose outputs are all written: what a farm log shows of it.
struct FrameReport {
  const char* step = "run";  ///< "run", "track" (--track-only) or "synth"
  int frame = 0;
  double seconds = 0.0;  ///< wall time from reading its mesh to its last file
  int patches = -1;      ///< patches on the frame; −1 for a method without patches
};

class Reporter {
 public:
  virtual ~Reporter() = default;
  /// Normal messages (suppressed by -q).
  virtual void info(const std::string& message) { (void)message; }
  /// Details shown with -v.
  virtual void verbose(const std::string& message) { (void)message; }
  /// Something the user should know about; never suppressed by -q.
  virtual void warn(const std::string& message) { (void)message; }
  /// Frame `done` of `total` is in `stage` (for a progress line).
  virtual void progress(std::size_t done, std::size_t total, const std::string& stage) {
    (void)done, (void)total, (void)stage;
  }
  /// A frame is finished (called in frame order, from one thread at a time).
  virtual void frame_done(const FrameReport& report) { (void)report; }
};

/// A reporter that says nothing (tests, library callers).
inline Reporter& silent_reporter() {
  static Reporter r;
  return r;
}

}  // namespace fluidtex
