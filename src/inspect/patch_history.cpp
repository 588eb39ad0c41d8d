#include "fluidtex/inspect/patch_history.h"

#include <cmath>
#include <string>
#include <utility>

#include "fluidtex/tracking/patch_counts.h"
#include "fluidtex/tracking/surface_change.h"

namespace fluidtex {

void PatchHistory::add(int frame, const Tracker& tracker, MetricRow& row) {
  const std::vector<Patch>& patches = tracker.patches();
  const PatchCounts counts = count_states(patches);
  row.emplace_back("patches", static_cast<double>(patches.size()));
  row.emplace_back("fading_in", counts.fading_in);
  row.emplace_back("active", counts.active);
  row.emplace_back("fading_out_distorted", counts.fading_out_distorted);
  row.emplace_back("fading_out_close", counts.fading_out_close);
  std::set<std::uint32_t> ids;
  int births = 0, recuts = 0;
  for (const Patch& p : patches) {
    ids.insert(p.id);
    if (!previous_ids_.count(p.id)) ++births, born_.emplace(p.id, frame);
    recuts += p.recut_frame == frame;
  }
  int deaths = 0;
  for (std::uint32_t id : previous_ids_) {
    if (ids.count(id)) continue;
    ++deaths;
    lifetimes_.push_back(frame - born_[id]);
    born_.erase(id);
  }
  row.emplace_back("births", have_previous_ ? births : std::nan(""));
  row.emplace_back("deaths", have_previous_ ? deaths : std::nan(""));
  row.emplace_back("recuts", have_previous_ ? recuts : std::nan(""));  // cut again in place (--distorted recut)
  // Churn: births per frame over live patches (a stepped run's pair spans
  // its step), and the share of patches active.
  row.emplace_back("birth_rate", have_previous_ && !patches.empty()
                                     ? births / static_cast<double>(patches.size()) / (frame - previous_frame_)
                                     : std::nan(""));
  row.emplace_back("active_share",
                   patches.empty() ? std::nan("") : counts.active / static_cast<double>(patches.size()));
  if (have_previous_) {
    for (auto& kv : retired_counts(tracker.retired())) row.push_back(std::move(kv));
    for (const RetiredPatch& r : tracker.retired()) ++retired_by_age_[static_cast<int>(r.cause)][age_bucket(r.age)];
  }
  previous_ids_ = std::move(ids);
  have_previous_ = true;
  previous_frame_ = frame;
}

void PatchHistory::finish(int last_frame) {
  for (const auto& [id, first] : born_) lifetimes_.push_back(last_frame - first + 1);
}

void ChangeHistory::add(int next_frame, const Tracker& tracker, double fps, MetricRow& row) {
  const std::shared_ptr<const SurfaceIndex> next = tracker.shared_surface();
  std::map<std::uint32_t, Vec3> now;
  for (const Patch& p : tracker.patches()) now.emplace(p.id, p.centre.point.position);
  if (first_density_ == 0.0 && next->area() > 0.0) first_density_ = static_cast<double>(now.size()) / next->area();
  if (surface_ && first_density_ > 0.0) {
    const TrackingOptions& o = tracker.settings().tracking;
    const int steps = next_frame - frame_;
    const SurfaceChange change = measure_surface_change(*surface_, *next, steps / fps, steps, o.d(), o.plane_angle);
    std::vector<SurfacePoint> at;
    for (const Patch& p : tracker.patches()) at.push_back(p.centre.point);
    std::vector<Vec3> births, removals;
    for (const auto& [id, x] : now)
      if (!centres_.count(id)) births.push_back(x);
    for (const auto& [id, x] : centres_)
      if (!now.count(id)) removals.push_back(x);
    const ChangeTally tally = tally_change(*next, change, at, births, removals);
    for (int c = 0; c < kChangeClasses; ++c) {
      const std::string name = change_class_name(c);
      row.emplace_back("density_" + name,
                       tally.area[c] > 0.0 ? tally.patches[c] / tally.area[c] / first_density_ : std::nan(""));
      row.emplace_back("births_" + name, tally.births[c]);
      row.emplace_back("removals_" + name, tally.removals[c]);
    }
    // The surface made per frame over the whole: at a constant patch
    // count per area, the least births per live patch a frame.
    row.emplace_back("surface_made", tally.made / next->area() / steps);
    row.emplace_back("surface_lost", tally.lost / next->area() / steps);
  }
  surface_ = next;
  centres_ = std::move(now);
  frame_ = next_frame;
}

}  // namespace fluidtex
