/// @file report.h
/// @brief How library stages talk to the user without owning a terminal: the
/// application passes a Reporter; the library calls it. Repeated warnings are
/// the caller's to batch (stages count per-patch failures and report once).
#pragma once

#include <string>

namespace fluidtex {

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
};

/// A reporter that says nothing (tests, library callers).
inline Reporter& silent_reporter() {
  static Reporter r;
  return r;
}

}  // namespace fluidtex
