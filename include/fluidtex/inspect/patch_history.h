/// @file patch_history.h
/// @brief `eval`'s figures that need the frame before: patch life (births,
/// deaths, recuts, lifetimes, churn, why patches leave) and where the
/// patches are against where the liquid makes and destroys surface, both
/// read from a run's consecutive state files.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <vector>

#include "fluidtex/geometry/surface.h"
#include "fluidtex/inspect/metric_row.h"
#include "fluidtex/tracking/fading.h"
#include "fluidtex/tracking/tracker.h"

namespace fluidtex {

/// Patches retired over a run, by the rule that retired them and their age
/// bucket then (fading.h: kRetireCauses × kAgeBuckets).
using RetiredByAge = std::array<std::array<int, kAgeBuckets>, kRetireCauses>;

/// Patch life over the frames: births, deaths, recuts, lifetimes, churn and
/// the removal histogram (rule × age), from consecutive state files.
class PatchHistory {
 public:
  /// Frame `frame`'s tracker (its state file): adds the patch counts by
  /// state, and from the second frame on births, deaths, recuts, churn and
  /// the patches retired per rule, to `row`.
  void add(int frame, const Tracker& tracker, MetricRow& row);
  /// Patches still alive after `last_frame` count with their (censored) age.
  void finish(int last_frame);

  /// Frames lived by the patches that died (and, after finish, by those alive).
  const std::vector<double>& lifetimes() const { return lifetimes_; }
  const RetiredByAge& retired_by_age() const { return retired_by_age_; }

 private:
  std::map<std::uint32_t, int> born_;  // live patch id -> first frame seen
  std::vector<double> lifetimes_;
  RetiredByAge retired_by_age_{};
  std::set<std::uint32_t> previous_ids_;
  bool have_previous_ = false;
  int previous_frame_ = 0;
};

/// Where the patches are against where the liquid makes and destroys
/// surface (surface_change.h), from consecutive state files: per class of
/// change, the patches per area over the first frame's patches per area,
/// and the pair's births and removals there (a removed patch at its last
/// centre, on the new surface).
class ChangeHistory {
 public:
  /// Frame `next_frame`'s tracker, `fps` frames a second: from the second
  /// frame on, adds the figures per class of change and the surface made
  /// and lost per frame to `row`.
  void add(int next_frame, const Tracker& tracker, double fps, MetricRow& row);

 private:
  std::shared_ptr<const SurfaceIndex> surface_;
  std::map<std::uint32_t, Vec3> centres_;
  int frame_ = 0;
  double first_density_ = 0.0;
};

}  // namespace fluidtex
