#include "fluidtex/tracking/tracker.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numeric>
#include <optional>

#include <oneapi/tbb/parallel_for.h>

#include "fluidtex/geometry/point_index.h"
#include "fluidtex/tracking/orientation.h"
#include "fluidtex/tracking/patch_builder.h"
#include "fluidtex/tracking/patch_coverage.h"
#include "fluidtex/tracking/patch_distortion.h"
#include "fluidtex/tracking/patch_locator.h"
#include "fluidtex/tracking/poisson.h"
#include "fluidtex/tracking/relaxation.h"
#include "fluidtex/util/memory.h"
#include "fluidtex/util/parallel.h"
#include "fluidtex/util/timing.h"

namespace fluidtex {

namespace {

PoissonParams poisson_params(const TrackingOptions& o) { return {o.d(), o.cs(), o.plane_angle, o.criterion}; }

/// A patch fading out because the surface around it is being destroyed.
/// A patch fading out because its surface is going (sunk, or carried out
/// through an outflow): it still counts as cover and as a disk until it is
/// gone, since a new disk there would go the same way, and its faces are
/// refilled when it is removed.
bool is_sinking(const Patch& p) {
  return is_fading_out(p.state) && (p.cause == RetireCause::Sunk || p.cause == RetireCause::Outflow);
}

/// One frame of a recut patch's recovery, at its fading rate.
void recover(Patch& p, double rate) {
  if (p.recovery.empty()) return;
  bool done = true;
  for (float& r : p.recovery) {
    r = static_cast<float>(std::min(1.0, r + rate));
    done = done && r >= 1.0f;
  }
  if (done) p.recovery.clear();
}

}  // namespace

std::vector<std::pair<std::string, double>> retired_counts(const std::vector<RetiredPatch>& retired) {
  std::array<int, kRetireCauses> causes{};
  std::array<int, kAgeBuckets> ages{};
  for (const RetiredPatch& r : retired) ++causes[static_cast<int>(r.cause)], ++ages[age_bucket(r.age)];
  std::vector<std::pair<std::string, double>> out;
  for (int c = 1; c < kRetireCauses; ++c)
    out.emplace_back(std::string("retired_") + to_string(static_cast<RetireCause>(c)), causes[c]);
  for (int b = 0; b < kAgeBuckets; ++b) out.emplace_back(std::string("retired_age_") + age_bucket_name(b), ages[b]);
  return out;
}

std::vector<std::pair<std::string, double>> recut_counts(const StepReport& step) {
  std::vector<std::pair<std::string, double>> out;
  for (int c = 1; c < kRetireCauses; ++c) {
    const auto cause = static_cast<RetireCause>(c);
    if (cause == RetireCause::Emptied || cause == RetireCause::TooClose || cause == RetireCause::Sunk ||
        cause == RetireCause::Outflow)
      continue;  // never recut
    out.emplace_back(std::string("recut_") + to_string(cause), step.recut_causes[c]);
  }
  return out;
}

PatchCounts count_states(const std::vector<Patch>& patches) {
  PatchCounts c;
  for (const Patch& p : patches) {
    switch (p.state) {
      case DiskState::FadingIn: ++c.fading_in; break;
      case DiskState::Active: ++c.active; break;
      case DiskState::FadingOutDistorted: ++c.fading_out_distorted; break;
      case DiskState::FadingOutClose: ++c.fading_out_close; break;
    }
  }
  return c;
}

Tracker::Tracker(TrackerSettings settings) : settings_(std::move(settings)) { settings_.tracking.validate(); }
Tracker::~Tracker() = default;
Tracker::Tracker(Tracker&&) noexcept = default;
Tracker& Tracker::operator=(Tracker&&) noexcept = default;

double tracking_memory_estimate(const SurfaceIndex& surface, const TrackingOptions& resolved, double patch_edge) {
  const double e = mean_edge_length(surface.mesh());
  const double d = resolved.d(), r = (1.0 + resolved.selection_margin) * d;
  const double selection = std::min(1.6 * M_PI * (r + e) * (r + e), 5.0 * M_PI * r * r);
  const double a = patch_edge > 0.0 ? patch_edge * d : e;  // remeshed, or the input's own triangles
  const double vertices = a > 0.0 ? selection / (0.5 * std::sqrt(3.0) * a * a) : 0.0;
  const double disks = surface.area() / (M_PI * d * d);
  return disks * kPatchesPerDisk * vertices * kBytesPerPatchVertex;
}

void check_disk_budget(const SurfaceIndex& surface, const TrackingOptions& resolved, double patch_edge) {
  const double d = resolved.d();
  const double disks = surface.area() / (M_PI * d * d);
  if (disks > static_cast<double>(kMaxDisks)) {
    throw InputError("", "--radius " + format_number(d) + " gives about " + std::to_string(std::llround(disks)) +
                             " Poisson disks on the first frame (at most " + std::to_string(kMaxDisks) +
                             "): raise --radius");
  }
  const double need = tracking_memory_estimate(surface, resolved, patch_edge);
  if (const std::optional<std::uint64_t> limit = memory_limit_bytes(); limit && need > static_cast<double>(*limit)) {
    char gigabytes[64];
    std::snprintf(gigabytes, sizeof gigabytes, "%.1f GB (this process may use %.1f GB)", need / 1e9,
                  static_cast<double>(*limit) / 1e9);
    throw InputError("", "--radius " + format_number(d) + " gives about " + std::to_string(std::llround(disks)) +
                             " Poisson disks on the first frame, whose patches need about " + gigabytes +
                             ": raise --radius");
  }
}

StepReport Tracker::step(std::shared_ptr<const FrameMesh> mesh, int frame, double dt) {
  StepReport report;
  report.frame = frame;
  step_dt_ = dt;
  std::shared_ptr<const SurfaceIndex> surface;
  {
    const ScopedStage stage(report.seconds, "surface");
    // The index refers to *mesh; holding the mesh in the deleter keeps it
    // alive as long as anyone holds the surface.
    surface.reset(new SurfaceIndex(*mesh), [mesh](const SurfaceIndex* s) { delete s; });
    if (!started_) {
      settings_.tracking = settings_.tracking.resolved(bounding_box(*mesh).diagonal());
      check_disk_budget(*surface, settings_.tracking, settings_.patch_edge);
    }
  }
  std::optional<SurfaceChange> change;
  if (started_) {
    const std::vector<AdvectResult> advected = advect(*surface, dt, report);  // 1
    retire_distorted(*surface, advected, frame, report);                      // 2
    change = measure_change(*surface, dt, frame, report);
    if (settings_.tracking.sink == Sink::Fade) track_sinking(*change, frame);
  }
  // Coverage is tested at points about a patch edge apart (the resolution
  // of the patch meshes), so that a face covered at its centroid cannot hide
  // a bare sliver.
  const FaceSamples samples = face_samples(*surface, coverage_spacing());
  std::vector<int> bare_faces;
  const std::vector<SurfaceSample> fresh = poisson_update(*surface, samples, frame, report, bare_faces);  // 3
  add_patches(*surface, fresh, frame, report);
  std::vector<int> vacated = fade(*surface, change ? &*change : nullptr, report);  // 4
  weigh(report);                                                                   // 5
  if (settings_.coverage_aware) {
    if (!started_) {
      bare_faces.resize(surface->mesh().triangles.size());
      std::iota(bare_faces.begin(), bare_faces.end(), 0);
    }
    // The Poisson update counted the sinking patches as cover; those gone
    // now leave their faces to the safety net.
    if (!vacated.empty()) {
      bare_faces.insert(bare_faces.end(), vacated.begin(), vacated.end());
      std::sort(bare_faces.begin(), bare_faces.end());
      bare_faces.erase(std::unique(bare_faces.begin(), bare_faces.end()), bare_faces.end());
    }
    refill_bare_faces(*surface, samples, std::move(bare_faces), frame, report);  // 6
  }
  if (change) tally_change(*surface, *change, report);

  std::sort(report.retired.begin(), report.retired.end(),
            [](const RetiredPatch& a, const RetiredPatch& b) { return a.id < b.id; });
  retired_ = report.retired;
  mesh_ = std::move(mesh);
  surface_ = std::move(surface);
  frame_ = frame;
  started_ = true;
  report.counts = count_states(patches_);
  for (const Patch& p : patches_) report.patch_vertices += p.num_vertices();
  return report;
}

void Tracker::prepend_retired(const std::vector<RetiredPatch>& earlier) {
  retired_.insert(retired_.begin(), earlier.begin(), earlier.end());
}

std::vector<AdvectResult> Tracker::advect(const SurfaceIndex& next, double dt, StepReport& report) {
  const ScopedStage stage(report.seconds, "advect");
  std::vector<AdvectResult> advected(patches_.size(), AdvectResult::Kept);
  parallel_each(patches_.size(), [&](std::size_t i) {
    advected[i] =
        advect_patch(patches_[i], *surface_, next, dt, settings_.tracking, settings_.advection, settings_.motion);
  });
  return advected;
}

namespace {

/// Removes the patches advection lost (counted in `report`, with their
/// removal and, unless already fading, the cause), and starts the fade-out
/// of those `distorted` names.
void drop_lost_flag_distorted(std::vector<Patch>& patches, const std::vector<AdvectResult>& advected,
                              const std::vector<RetireCause>& distorted, int frame, StepReport& report) {
  std::vector<Patch> kept;
  kept.reserve(patches.size());
  for (std::size_t i = 0; i < patches.size(); ++i) {
    Patch& p = patches[i];
    if (is_lost(advected[i])) {
      ++report.lost;
      report.removals.push_back(p.centre.point.position);
      if (!is_fading_out(p.state)) {
        const RetireCause cause =
            advected[i] == AdvectResult::CentreLost ? RetireCause::CentreLost : RetireCause::Emptied;
        report.retired.push_back({p.id, cause, frame - p.created_frame});
      }
      continue;
    }
    if (distorted[i] != RetireCause::None && !is_fading_out(p.state)) {
      p.state = DiskState::FadingOutDistorted;
      p.flagged_frame = frame;
      p.cause = distorted[i];
      report.retired.push_back({p.id, p.cause, frame - p.created_frame});
    }
    kept.push_back(std::move(p));
  }
  patches = std::move(kept);
}

}  // namespace

void Tracker::retire_distorted(const SurfaceIndex& surface, const std::vector<AdvectResult>& advected, int frame,
                               StepReport& report) {
  const ScopedStage stage(report.seconds, "distortion");
  const TrackingOptions& o = settings_.tracking;
  std::vector<RetireCause> distorted(patches_.size(), RetireCause::None);
  std::vector<char> relaxed(patches_.size(), 0);
  std::vector<RetireCause> recut_cause(patches_.size(), RetireCause::None);
  parallel_each(patches_.size(), [&](std::size_t i) {
    if (is_lost(advected[i])) return;
    if (o.relax_frames > 0 && !is_fading_out(patches_[i].state))
      relaxed[i] = relax_patch(patches_[i], 1.0 / o.relax_frames, o.relax_yield(), o);
    distorted[i] = update_distortion(patches_[i], surface, o);
    // The per-vertex rules retire a patch for any vertex lost inside the
    // disk; the patch-scale test weighs the lost part in update_distortion.
    if (distorted[i] == RetireCause::None && advected[i] == AdvectResult::Damaged &&
        o.distortion_test == DistortionTest::Vertex) {
      distorted[i] = RetireCause::VerticesLost;
    }
    // A patch whose centre was moved back onto the surface is recut around
    // it, or fades out (as lost) where no patch can be cut there.
    const bool moved = advected[i] == AdvectResult::CentreMoved;
    if (moved && distorted[i] == RetireCause::None) distorted[i] = RetireCause::CentreLost;
    // A patch whose centre left through an outflow fades out on the rim.
    if (advected[i] == AdvectResult::LeftThroughRim) {
      distorted[i] = RetireCause::Outflow;
      return;
    }
    if (distorted[i] != RetireCause::None && o.distorted == Distorted::Recut && !is_fading_out(patches_[i].state)) {
      std::optional<Patch> recut =
          recut_patch(patches_[i], surface, o, settings_.seed, frame, settings_.patch_edge * o.d());
      if (recut) {
        update_distortion(*recut, surface, o);
        patches_[i] = std::move(*recut);
        recut_cause[i] = distorted[i];
        distorted[i] = RetireCause::None;
      }
    }
  });
  report.relaxed = static_cast<int>(std::count(relaxed.begin(), relaxed.end(), 1));
  for (const RetireCause cause : recut_cause) {
    if (cause != RetireCause::None) ++report.recut, ++report.recut_causes[static_cast<int>(cause)];
  }
  drop_lost_flag_distorted(patches_, advected, distorted, frame, report);
}

std::vector<SurfaceSample> Tracker::retire_too_close(const PoissonParams& params, int frame, StepReport& report) {
  const TrackingOptions& o = settings_.tracking;
  // Fading-out disks are ignored; patches are in id order, so of two disks
  // too close the younger one fades out, once it has been too close for
  // more than kill-frames frames in a row.
  std::vector<std::size_t> live;
  std::vector<SurfaceSample> disks;
  for (std::size_t i = 0; i < patches_.size(); ++i) {
    if (is_fading_out(patches_[i].state)) continue;
    live.push_back(i);
    disks.push_back(patches_[i].centre);
  }
  auto covers_centre = [&](std::size_t older, std::size_t younger) {
    return patch_covers(patches_[live[older]], disks[younger].point.position, disks[younger].normal, o.mpt());
  };
  const std::vector<bool> close =
      flag_too_close(disks, params, o.kill_alpha,
                     settings_.coverage_aware ? std::function<bool(std::size_t, std::size_t)>(covers_centre) : nullptr);
  // A sunk patch keeps its disk and its cover while it fades: the surface
  // it stood for is going, and a new disk there would sink in turn.
  std::vector<SurfaceSample> remaining;
  for (const Patch& p : patches_)
    if (is_sinking(p)) remaining.push_back(p.centre);
  for (std::size_t k = 0; k < live.size(); ++k) {
    Patch& p = patches_[live[k]];
    p.close_frames = close[k] ? p.close_frames + 1 : 0;
    // Where the surface has lost the fraction α of its area over about the
    // last kill-frames frames, the pair will not part again: no wait.
    const bool sinking = o.sink == Sink::Fade && p.sunk < std::log(1.0 - o.kill_alpha);
    if (p.close_frames > (sinking ? 0 : o.kill_frames)) {
      p.state = DiskState::FadingOutClose;
      p.flagged_frame = frame;
      p.cause = sinking ? RetireCause::Sunk : RetireCause::TooClose;
      report.retired.push_back({p.id, p.cause, frame - p.created_frame});
    } else {
      remaining.push_back(disks[k]);
    }
  }
  return remaining;
}

namespace {

/// The Poisson update's candidates and which of them no live patch covers
/// (K_S > 0): the random candidates, then the first bare sample of every face
/// left bare, in face order (random candidates miss thin strips, such as the
/// fillet where a liquid surface meets a wall, narrower than their spacing).
class GapSearch {
 public:
  GapSearch(const SurfaceIndex& surface, const FaceSamples& samples, std::vector<SurfaceSample> candidates)
      : surface_(surface), samples_(samples), candidates_(std::move(candidates)), random_(candidates_.size()) {}

  /// Tests every candidate and face against the patches of `live_mask`.
  void find(const std::vector<Patch>& patches, const std::vector<char>& live_mask, double mpt) {
    coverage_.emplace(patches, mpt, &live_mask);
    candidates_.resize(random_);
    uncovered_ = uncovered_samples(candidates_, *coverage_);
    const BareFaces bare = fluidtex::bare_faces(surface_, samples_, *coverage_);
    bare_faces_ = bare.face;
    candidates_.insert(candidates_.end(), bare.point.begin(), bare.point.end());
    uncovered_.resize(candidates_.size(), 1);
  }

  /// The same after patches were cut again, computed only where their
  /// coverage can have changed (`changed`): the random candidates and the
  /// faces there are tested again, the rest keep their first answer.
  void refind(const std::vector<Patch>& patches, const std::vector<char>& live_mask, double mpt,
              const std::vector<BBox>& changed) {
    coverage_.emplace(patches, mpt, &live_mask);
    auto inside = [&](const Vec3& q) {
      return std::any_of(changed.begin(), changed.end(), [&](const BBox& b) {
        return (q.array() >= b.min.array()).all() && (q.array() <= b.max.array()).all();
      });
    };
    const std::vector<SurfaceSample> first_points(candidates_.begin() + static_cast<std::ptrdiff_t>(random_),
                                                  candidates_.end());
    candidates_.resize(random_);
    uncovered_.resize(random_);
    std::vector<std::size_t> again;
    for (std::size_t k = 0; k < random_; ++k) {
      if (inside(candidates_[k].point.position)) again.push_back(k);
    }
    parallel_each(again.size(), [&](std::size_t a) {
      const SurfaceSample& c = candidates_[again[a]];
      uncovered_[again[a]] = !coverage_->covers(c.point.position, c.normal);
    });
    std::vector<int> faces;
    for (const BBox& b : changed) {
      const std::vector<int> in = surface_.faces_in_box(b.min, b.max);
      faces.insert(faces.end(), in.begin(), in.end());
    }
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    merge_bare_faces(faces, first_points, fluidtex::bare_faces(surface_, samples_, *coverage_, &faces));
  }

  std::vector<SurfaceSample>& candidates() { return candidates_; }
  std::vector<char>& uncovered() { return uncovered_; }
  std::vector<int>& bare_faces() { return bare_faces_; }
  const PatchCoverage& coverage() const { return *coverage_; }

 private:
  /// The bare faces of the first test (their points `first_points`) and
  /// those of `retested` (the faces `faces` tested again), ascending by
  /// face: a face tested again takes its new answer.
  void merge_bare_faces(const std::vector<int>& faces, const std::vector<SurfaceSample>& first_points,
                        const BareFaces& retested) {
    std::vector<int> merged_face;
    std::vector<SurfaceSample> merged_point;
    std::size_t a = 0, b = 0;
    auto from_first = [&](std::size_t k) { return !std::binary_search(faces.begin(), faces.end(), bare_faces_[k]); };
    while (a < bare_faces_.size() || b < retested.face.size()) {
      if (b == retested.face.size() || (a < bare_faces_.size() && bare_faces_[a] < retested.face[b])) {
        if (from_first(a)) merged_face.push_back(bare_faces_[a]), merged_point.push_back(first_points[a]);
        ++a;
      } else {
        if (a < bare_faces_.size() && bare_faces_[a] == retested.face[b]) ++a;
        merged_face.push_back(retested.face[b]), merged_point.push_back(retested.point[b]);
        ++b;
      }
    }
    bare_faces_ = std::move(merged_face);
    candidates_.insert(candidates_.end(), merged_point.begin(), merged_point.end());
    uncovered_.resize(candidates_.size(), 1);
  }

  const SurfaceIndex& surface_;
  const FaceSamples& samples_;
  std::vector<SurfaceSample> candidates_;
  std::size_t random_;
  std::vector<char> uncovered_;
  std::vector<int> bare_faces_;
  std::optional<PatchCoverage> coverage_;
};

}  // namespace

std::vector<SurfaceSample> Tracker::poisson_update(const SurfaceIndex& surface, const FaceSamples& samples, int frame,
                                                   StepReport& report, std::vector<int>& bare_faces) {
  const ScopedStage stage(report.seconds, "poisson");
  const TrackingOptions& o = settings_.tracking;
  const PoissonParams params = poisson_params(o);
  const std::vector<SurfaceSample> remaining = retire_too_close(params, frame, report);
  GapSearch gaps(surface, samples, surface_candidates(surface, o.d(), settings_.seed, settings_.candidates_per_disk));
  std::function<bool(std::size_t)> reached;
  std::vector<PatchHit> hits;
  if (started_ && settings_.coverage_aware) {
    // A disk waiting out kill-frames within the kill distance still counts
    // as cover: it is live and textured, and most such pairs part again. Its
    // area is refilled when it starts to fade out (the new disk fades in as
    // it fades out). Counted as bare, it seeded disks beside it that stayed
    // when the pair parted (docs/tracking.md, "Waiting disks count as cover").
    // A sinking patch counts as cover until it is gone. Their weights are
    // refreshed for the advected shape first.
    std::vector<char> live_mask(patches_.size(), 0);
    for (std::size_t i = 0; i < patches_.size(); ++i)
      live_mask[i] = !is_fading_out(patches_[i].state) || is_sinking(patches_[i]);
    parallel_each(patches_.size(), [&](std::size_t i) {
      if (live_mask[i]) update_weights(patches_[i], o);
    });
    gaps.find(patches_, live_mask, o.mpt());
    if (o.gap_fill == GapFill::Recut) {
      const std::vector<BBox> changed =
          regrow_over_gaps(surface, gaps.candidates(), gaps.uncovered(), live_mask, frame, report);
      if (!changed.empty()) gaps.refind(patches_, live_mask, o.mpt(), changed);
    }
    bare_faces = gaps.bare_faces();
    // The birth margin measured on the patches too: a live patch stretched
    // by the liquid still shows its own disk where its centre has moved more
    // than (1 + γ)·d away in space. A gap the liquid opens inside a patch
    // seeds nothing until the patch yields (relax-frames) or is recut, so a
    // stretch the liquid undoes leaves no extra disks behind (docs/tracking.md,
    // "The birth margin measured in the patches' uv").
    const double reach = (1.0 + o.birth_margin) * o.d();
    if (o.birth_gap == BirthGap::Patches)
      reached = [&, reach](std::size_t k) {
        const SurfaceSample& c = gaps.candidates()[k];
        gaps.coverage().locate(c.point.position, c.normal, hits);
        return std::any_of(hits.begin(), hits.end(), [&](const PatchHit& h) { return h.uv.norm() < reach; });
      };
  }
  return fill_gaps(remaining, gaps.candidates(), surface, params, settings_.min_component_area * M_PI * o.d() * o.d(),
                   gaps.uncovered().empty() ? nullptr : &gaps.uncovered(), o.birth_margin, reached);
}

std::vector<BBox> Tracker::regrow_over_gaps(const SurfaceIndex& surface, const std::vector<SurfaceSample>& candidates,
                                            const std::vector<char>& uncovered, const std::vector<char>& live_mask,
                                            int frame, StepReport& report) {
  const TrackingOptions& o = settings_.tracking;
  const PoissonParams params = poisson_params(o);
  std::vector<std::size_t> owner;  // patch index per centre in `centres`
  std::vector<Vec3> centres;
  for (std::size_t i = 0; i < patches_.size(); ++i) {
    if (live_mask[i] && !is_fading_out(patches_[i].state))
      owner.push_back(i), centres.push_back(patches_[i].centre.point.position);
  }
  const PointIndex index(centres);
  // Each bare candidate goes to the nearest live disk whose Poisson
  // criterion at radius d rejects it: the disk that stands for that surface.
  std::vector<std::size_t> regrow;
  std::vector<int> near;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    if (!uncovered[k]) continue;
    const SurfaceSample& c = candidates[k];
    index.within(c.point.position, std::max(o.d(), o.cs()), near);
    std::sort(near.begin(), near.end());
    double best = std::numeric_limits<double>::infinity();
    std::size_t chosen = patches_.size();
    for (int j : near) {
      const SurfaceSample& disk = patches_[owner[j]].centre;
      const double dist = (disk.point.position - c.point.position).squaredNorm();
      if (dist < best && rejects(disk.point.position, disk.normal, c.point.position, c.normal, o.d(), params))
        best = dist, chosen = owner[j];
    }
    if (chosen < patches_.size()) regrow.push_back(chosen);
  }
  std::sort(regrow.begin(), regrow.end());
  regrow.erase(std::unique(regrow.begin(), regrow.end()), regrow.end());
  std::vector<std::optional<BBox>> changed(regrow.size());
  const Vec3 pad = Vec3::Constant(2.0 * o.mpt());
  parallel_each(regrow.size(), [&](std::size_t r) {
    Patch& p = patches_[regrow[r]];
    std::optional<Patch> recut = recut_patch(p, surface, o, settings_.seed, frame, settings_.patch_edge * o.d());
    if (!recut) return;
    update_distortion(*recut, surface, o);
    update_weights(*recut, o);
    const BBox before = bounding_box(p.positions), after = bounding_box(recut->positions);
    changed[r] = BBox{before.min.cwiseMin(after.min) - pad, before.max.cwiseMax(after.max) + pad};
    p = std::move(*recut);
  });
  std::vector<BBox> boxes;
  for (const auto& box : changed) {
    if (box) boxes.push_back(*box);
  }
  report.regrown += static_cast<int>(boxes.size());
  return boxes;
}

void Tracker::add_patches(const SurfaceIndex& surface, const std::vector<SurfaceSample>& fresh, int frame,
                          StepReport& report) {
  const ScopedStage stage(report.seconds, "patches");
  build_patches(surface, fresh, frame, report);
}

void Tracker::build_patches(const SurfaceIndex& surface, const std::vector<SurfaceSample>& fresh, int frame,
                            StepReport& report) {
  const TrackingOptions& o = settings_.tracking;
  // Built in parallel; ids are fixed before the loop. Each is turned to
  // the orientation field of the patches there before the batch.
  std::unique_ptr<PatchCoverage> coverage;
  if (o.orientation != Orientation::Random && !patches_.empty() && !fresh.empty())
    coverage = std::make_unique<PatchCoverage>(patches_, o.mpt());
  const OrientationContext orient{surface, patches_, coverage.get(), step_dt_};
  std::vector<std::optional<Patch>> built(fresh.size());
  parallel_each(fresh.size(), [&](std::size_t i) {
    built[i] = build_patch(surface, fresh[i], o, next_id_ + static_cast<std::uint32_t>(i), settings_.seed, frame,
                           settings_.patch_edge * o.d());
    if (!built[i]) return;
    turn_uv(*built[i], orientation_angle(*built[i], orient, o));
    update_distortion(*built[i], surface, o);
  });
  next_id_ += static_cast<std::uint32_t>(fresh.size());
  if (o.orientation != Orientation::Random) {
    std::vector<Patch*> batch;
    for (std::optional<Patch>& p : built) {
      if (p) batch.push_back(&*p);
    }
    separate_anchors(batch, patches_, o.d(), settings_.seed);
  }
  for (std::optional<Patch>& p : built) {
    if (!p) {
      ++report.failed;
      continue;
    }
    report.births.push_back(p->centre.point.position);
    p->state = started_ ? DiskState::FadingIn : DiskState::Active;
    p->kt = started_ ? 0.0 : 1.0;
    patches_.push_back(std::move(*p));
    ++report.created;
  }
}

void Tracker::refill_bare_faces(const SurfaceIndex& surface, const FaceSamples& samples, std::vector<int> faces,
                                int frame, StepReport& report) {
  const ScopedStage stage(report.seconds, "refill");
  const TrackingOptions& o = settings_.tracking;
  // Faces a refill patch was already centred on: one still bare after that
  // is not covered by a patch of its own, and as a candidate it would keep
  // rejecting its neighbours' candidates. Blender-obstacle's torn sheet
  // (frames 14 and 16 of the cut 12-22) still has such faces; its folded
  // face on frame 20 was one until SurfaceIndex::normal_at gave it its own
  // normal instead of the vertex normals' blend, which points behind it.
  std::vector<int> tried;
  for (int round = 0; round < kRefillRounds && !faces.empty(); ++round) {
    const PatchCoverage coverage(patches_, o.mpt());
    BareFaces bare = fluidtex::bare_faces(surface, samples, coverage, &faces);
    if (bare.face.empty()) return;
    const std::vector<SurfaceSample>& candidates = bare.point;
    std::vector<int> still = std::move(bare.face);
    // Greedy in face order, the Poisson criterion among themselves only.
    const std::vector<SurfaceSample> fresh = fill_gaps({}, candidates, surface, poisson_params(o), 0.0);
    const std::size_t first = patches_.size();
    build_patches(surface, fresh, frame, report);
    // The new patches' first frame, as fade() and weigh() gave the others.
    std::vector<SurfaceSample> all;
    all.reserve(patches_.size());
    for (const Patch& p : patches_) all.push_back(p.centre);
    const std::vector<int> rho = disk_density(all, poisson_params(o));
    for (std::size_t i = first; i < patches_.size(); ++i) {
      Patch& p = patches_[i];
      p.density = rho[i];
      if (started_) {
        const FadeResult r = fade_step(p.state, p.kt, rho[i], o.fade_frames, o.fading, p.motion);
        p.state = r.state, p.kt = r.kt;
      }
      update_weights(p, o);
    }
    report.refilled += static_cast<int>(patches_.size() - first);
    for (const SurfaceSample& f : fresh) tried.push_back(f.point.face);
    std::sort(tried.begin(), tried.end());
    std::erase_if(still, [&](int f) { return std::binary_search(tried.begin(), tried.end(), f); });
    faces = std::move(still);
  }
}

std::vector<int> Tracker::fade(const SurfaceIndex& surface, const SurfaceChange* change, StepReport& report) {
  const ScopedStage stage(report.seconds, "fading");
  const TrackingOptions& o = settings_.tracking;
  std::vector<SurfaceSample> all;
  all.reserve(patches_.size());
  for (const Patch& p : patches_) all.push_back(p.centre);
  const std::vector<int> rho = disk_density(all, poisson_params(o));
  const int steps = std::max(1, report.frame - frame_);
  std::vector<Patch> survivors;
  survivors.reserve(patches_.size());
  std::vector<int> vacated;
  for (std::size_t i = 0; i < patches_.size(); ++i) {
    Patch& p = patches_[i];
    p.density = rho[i];
    // A sunk patch is gone by the time the surface around it has lost
    // another α of its area: where the liquid destroys surface faster than
    // the fade would take, the patches carried in would stack up there.
    // (The change is per frame; a step of several frames fades once.)
    double at_least = 0.0;
    if (change && p.cause == RetireCause::Sunk && is_fading_out(p.state)) {
      at_least = steps * std::max(0.0, -change->at(p.centre.point)) / -std::log(1.0 - o.kill_alpha);
    }
    const FadeResult r = fade_step(p.state, p.kt, rho[i], o.fade_frames, o.fading, p.motion, at_least);
    if (r.remove) {
      ++report.removed;
      report.removals.push_back(p.centre.point.position);
      // Every face its triangles may reach, not only those under its
      // vertices: a patch edge spans several faces of a fine surface.
      if (is_sinking(p)) {
        const BBox box = bounding_box(p.positions);
        const Vec3 pad = Vec3::Constant(o.mpt());
        const std::vector<int> reach = surface.faces_in_box(box.min - pad, box.max + pad);
        vacated.insert(vacated.end(), reach.begin(), reach.end());
      }
      continue;
    }
    p.state = r.state;
    p.kt = r.kt;
    recover(p, fade_rate(rho[i], o.fade_frames, o.fading, p.motion));
    survivors.push_back(std::move(p));
  }
  patches_ = std::move(survivors);
  report.removed += report.lost;
  return vacated;
}

void Tracker::track_sinking(const SurfaceChange& change, int frame) {
  const TrackingOptions& o = settings_.tracking;
  // A sum of the rates with weights decaying by 1 − 1/kill-frames a frame
  // (about the last kill-frames frames): a step of n frames decays it n
  // times and adds its rate, per frame, n times.
  const double keep = 1.0 - 1.0 / std::max(1, o.kill_frames);
  const int steps = std::max(1, frame - frame_);
  const double decay = std::pow(keep, steps);
  const double gain = keep < 1.0 ? (1.0 - decay) / (1.0 - keep) : 1.0;
  for (Patch& p : patches_) {
    if (!is_fading_out(p.state)) p.sunk = decay * p.sunk + gain * change.at(p.centre.point);
  }
}

SurfaceChange Tracker::measure_change(const SurfaceIndex& surface, double dt, int frame, StepReport& report) const {
  const ScopedStage stage(report.seconds, "change");
  const TrackingOptions& o = settings_.tracking;
  return measure_surface_change(*surface_, surface, dt, std::max(1, frame - frame_), o.d(), o.plane_angle);
}

void Tracker::tally_change(const SurfaceIndex& surface, const SurfaceChange& change, StepReport& report) const {
  const ScopedStage stage(report.seconds, "change_tally");
  std::vector<SurfacePoint> centres;
  centres.reserve(patches_.size());
  for (const Patch& p : patches_) centres.push_back(p.centre.point);
  report.change = fluidtex::tally_change(surface, change, centres, report.births, report.removals);
}

void Tracker::weigh(StepReport& report) {
  const ScopedStage stage(report.seconds, "weights");
  parallel_each(patches_.size(), [&](std::size_t i) { update_weights(patches_[i], settings_.tracking); });
}

}  // namespace fluidtex
