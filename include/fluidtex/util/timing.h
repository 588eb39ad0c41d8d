/// @file timing.h
/// @brief Wall-clock stage timing, as `stats.jsonl` reports it: a list of
/// (stage name, seconds) in the order the stages ran.
#pragma once

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace fluidtex {

using StageSeconds = std::vector<std::pair<std::string, double>>;
using Clock = std::chrono::steady_clock;

/// Seconds of wall time since `start`.
inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// Times the enclosing scope: on leaving it, appends (name, seconds) to `out`.
class ScopedStage {
 public:
  ScopedStage(StageSeconds& out, std::string name) : out_(out), name_(std::move(name)), start_(Clock::now()) {}
  ~ScopedStage() { out_.emplace_back(std::move(name_), seconds_since(start_)); }
  ScopedStage(const ScopedStage&) = delete;
  ScopedStage& operator=(const ScopedStage&) = delete;

 private:
  StageSeconds& out_;
  std::string name_;
  Clock::time_point start_;
};

}  // namespace fluidtex
