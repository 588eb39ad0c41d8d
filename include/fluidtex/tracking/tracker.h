/// @file tracker.h
/// @brief Patch tracking over a sequence (Gagnon et al. 2019, Secs. 4–6.3):
/// the per-frame update of the Poisson-disk distribution of deformable
/// patches. Per frame, in order (docs/method.md):
///  1. advect every disk centre and patch vertex, project onto the new surface
///     (vertices beyond mpt are removed, a centre beyond mpt kills its patch);
///  2. distortion → a too distorted patch is cut again in place
///     (recut_patch; --distorted recut, the default), or "fading out (too
///     distorted)" (--distorted fade, the paper, or when no patch can be cut);
///  3. Poisson update ignoring fading-out disks: kill distance → "fading out
///     (too close)", new disks in the gaps, their patches created;
///  4. density ρ and K_t (Eq. 6 or 5); fading-out patches at K_t ≤ 0 removed;
///  5. vertex weights w_V = K_S·K_t;
///  6. coverage safety net: faces still bare get a disk at their centroid
///     and a patch (refill_bare_faces).
/// The first frame gets a fresh distribution whose patches start active.
///
/// Parallel (oneTBB) over patches for advection, distortion, creation and
/// weights; every loop writes only its own slot and every random number is a
/// hash of (seed, frame, item), so results are identical for any thread count.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fluidtex/tracking/advection.h"
#include "fluidtex/tracking/options.h"
#include "fluidtex/tracking/patch.h"
#include "fluidtex/tracking/patch_counts.h"
#include "fluidtex/tracking/patch_coverage.h"
#include "fluidtex/tracking/surface_change.h"
#include "fluidtex/util/timing.h"

namespace fluidtex {

/// Most Poisson disks a first frame may ask for (surface area / πd²): a
/// radius far below the scene's detail would take hours and gigabytes.
inline constexpr long long kMaxDisks = 2000000;

/// The memory tracking takes, estimated before the first frame: patches
/// (kPatchesPerDisk per disk of area πd², as Poisson disks pack), each with
/// the vertices its selection remeshes to at edges of patch_edge·d, each
/// vertex taking about kBytesPerPatchVertex with everything that follows it
/// (the patch, its state, the coverage and locator indices, synthesis's
/// bins). A selection is the triangles reaching into the ball of radius
/// r = (1 + β)·d, about π(r + e)² for the input's mean edge e, with 1.6
/// times the vertices of its area (remeshing splits the input's border
/// edges), or, cut to its cube on a coarse input, about 5 balls (a plane's
/// section of the cube, 16 r²). Measured (patches per disk, vertices per
/// patch, peak resident memory against the estimate):
///
/// | input | --radius | patches/disk | vertices/patch (estimate) | memory (estimate) |
/// |---|---|---|---|---|
/// | rotation, 16 cells (edges 4.7·d) | 0.03 | 1.9 | 401 (382) | 1.17 GB (1.2) |
/// | rotation, 16 cells (edges 7·d) | 0.02 | 1.9 | 295 (380) | 1.71 GB (2.7) |
/// | blender-drop, frames 1–2 (edges about d) | 0.02 | 1.9 | 153 (327) | 1.40 GB (2.1) |
///
/// The estimate is up to 1.6 times the need: a job is refused only when the
/// estimate exceeds what the process may use.
inline constexpr double kPatchesPerDisk = 1.9;
inline constexpr double kBytesPerPatchVertex = 1500.0;

/// The estimate above for the first frame, in bytes.
double tracking_memory_estimate(const SurfaceIndex& surface, const TrackingOptions& resolved, double patch_edge);

/// InputError naming --radius, before tracking, when the first frame's
/// surface would hold more than kMaxDisks disks of the resolved radius, or
/// when their patches would need more memory (tracking_memory_estimate)
/// than the process may use (memory_limit_bytes), with the estimate.
void check_disk_budget(const SurfaceIndex& surface, const TrackingOptions& resolved, double patch_edge);

struct TrackerSettings {
  TrackingOptions tracking;  ///< Table 3/4 parameters (resolved on the first frame)
  Advection advection = Advection::Euler;
  PatchMotion motion = PatchMotion::Smooth;
  std::uint64_t seed = 1;
  double candidates_per_disk = 32.0;  ///< dart-throwing candidates per disk area π d²
  /// Components smaller than this × π d² may stay without a disk.
  double min_component_area = 0.02;
  /// Insert disks where no live patch covers the surface even if a disk
  /// centre is near (see fill_gaps); off gives the paper's centre-only test.
  bool coverage_aware = true;
  /// Patch triangles are remeshed to edges of this × d (≤ 0 keeps the
  /// surface's own triangles; see build_patch). 0.35: edges of d/4 carry
  /// twice the vertices for the same texture and churn on the real caches
  /// (docs/performance.md).
  double patch_edge = 0.35;
};

/// Coverage (the gap test, the safety net, uncovered_area_fraction) is tested
/// at points this × d apart inside every face (face_samples): finer than the
/// patch meshes, so that a face covered at one point cannot hide a bare
/// sliver (d/2 left bare surface on the real caches).
inline constexpr double kCoverageSpacing = 0.25;

/// A patch that started leaving the distribution in a step: the rule that
/// fired and its age then (frames since its creation).
struct RetiredPatch {
  std::uint32_t id = 0;
  RetireCause cause = RetireCause::None;
  int age = 0;
};

struct StepReport {
  int frame = 0;
  PatchCounts counts;
  int created = 0;   ///< new patches this frame (refilled ones included)
  int refilled = 0;  ///< of those, made by the coverage safety net (refill_bare_faces)
  int relaxed = 0;   ///< live patches whose uv relaxed (stretched beyond the yield; relax-frames)
  int recut = 0;     ///< patches found too distorted and cut again in place (--distorted recut)
  int regrown = 0;   ///< live patches cut again to cover bare surface by their disk (--gap-fill recut)
  std::array<int, kRetireCauses> recut_causes{};  ///< of those, by the rule that would have retired them
  int removed = 0;                                ///< patches removed (faded out or lost)
  int lost = 0;                                   ///< of those, lost in advection (centre beyond mpt, no triangle left)
  int failed = 0;                                 ///< disks whose patch could not be built (logged in aggregate)
  std::vector<RetiredPatch> retired;              ///< patches flagged or lost this step, in id order
  std::size_t patch_vertices = 0;
  /// Where the step made and destroyed surface (surface_change.h), and the
  /// patches, births and removals there; not measured on the first frame.
  ChangeTally change;
  /// The new patches' centres and the removed patches' last centres (those
  /// lost in advection: where they were on the previous frame), in the
  /// order they were made and removed.
  std::vector<Vec3> births, removals;
  StageSeconds seconds;  ///< per stage
};

class Tracker {
 public:
  explicit Tracker(TrackerSettings settings);
  ~Tracker();
  Tracker(Tracker&&) noexcept;
  Tracker& operator=(Tracker&&) noexcept;

  /// Advances to `mesh` (frame number `frame`, `dt` seconds after the previous
  /// step). The tracker keeps the mesh for the next step.
  StepReport step(std::shared_ptr<const FrameMesh> mesh, int frame, double dt);

  const std::vector<Patch>& patches() const { return patches_; }
  /// The patches that started leaving the distribution in the last step
  /// (flagged to fade out, or lost at once), with the rule that fired.
  const std::vector<RetiredPatch>& retired() const { return retired_; }
  /// Puts `earlier` (the retirements of steps whose state is not saved: the
  /// frames a stepped run follows without writing) before the last step's,
  /// so that the next saved state lists every retirement since the one before.
  void prepend_retired(const std::vector<RetiredPatch>& earlier);
  /// The parameters in use; lengths are resolved after the first step.
  const TrackerSettings& settings() const { return settings_; }
  /// How far apart the points are at which coverage is tested
  /// (face_samples): kCoverageSpacing × d.
  double coverage_spacing() const { return kCoverageSpacing * settings_.tracking.d(); }
  const SurfaceIndex* surface() const { return surface_.get(); }
  /// The current surface, shared: it stays valid after later steps (the
  /// pipeline synthesises frame t while the tracker moves on to t + 1).
  std::shared_ptr<const SurfaceIndex> shared_surface() const { return surface_; }
  std::shared_ptr<const FrameMesh> mesh() const { return mesh_; }
  int frame() const { return frame_; }
  bool started() const { return started_; }

  /// Binary state (versioned): settings, frame, next id and every patch, so a
  /// later process can resume tracking or synthesise this frame. The surface
  /// is not stored: resuming re-reads the frame's mesh and checks it matches.
  void save(const std::string& path) const;
  /// The bytes save() writes: pack_state(unpacked_state()).
  std::string serialize() const;
  /// The state before packing: a copy of the fields, cheap enough for the
  /// pipeline's serial tracking stage, so that packing (pack_state, the
  /// costly half) runs in parallel with the next frame's tracking.
  struct UnpackedState {
    std::array<std::string, 3> streams;  ///< the 8-, 4- and 1-byte fields, in serialisation order
  };
  UnpackedState unpacked_state() const;
  static std::string pack_state(const UnpackedState& state);
  /// Restores a saved state onto `mesh` (the same frame's mesh, read again);
  /// InputError when the file is not a valid state, is another frame's than
  /// `frame` (when given: the frame its name says) or does not match `mesh`.
  static Tracker load(const std::string& path, std::shared_ptr<const FrameMesh> mesh,
                      std::optional<int> frame = std::nullopt);

 private:
  // The steps of step(), in order (see the file comment).
  std::vector<AdvectResult> advect(const SurfaceIndex& next, double dt, StepReport& report);
  void retire_distorted(const SurfaceIndex& surface, const std::vector<AdvectResult>& advected, int frame,
                        StepReport& report);
  std::vector<SurfaceSample> poisson_update(const SurfaceIndex& surface, const FaceSamples& samples, int frame,
                                            StepReport& report, std::vector<int>& bare_faces);
  /// The kill distance (Sec. 5.4): of two live disks too close, the younger
  /// fades out once it has been too close for more than kill-frames frames
  /// in a row (at once where the surface sinks). Returns the disks that
  /// stay: the live ones left and the sinking ones.
  std::vector<SurfaceSample> retire_too_close(const PoissonParams& params, int frame, StepReport& report);
  /// GapFill::Recut: every live patch (live_mask) whose disk rejects one of
  /// the `uncovered` `candidates` at radius d (the nearest such disk, for
  /// each) is cut again around its centre from `surface` (recut_patch), so
  /// that it covers the bare surface it stands for. Returns, per patch cut
  /// again, the box its coverage can have changed in: the bounding box of
  /// its old and new vertices, grown by twice the projection tolerance.
  std::vector<BBox> regrow_over_gaps(const SurfaceIndex& surface, const std::vector<SurfaceSample>& candidates,
                                     const std::vector<char>& uncovered, const std::vector<char>& live_mask, int frame,
                                     StepReport& report);
  void add_patches(const SurfaceIndex& surface, const std::vector<SurfaceSample>& fresh, int frame, StepReport& report);
  void build_patches(const SurfaceIndex& surface, const std::vector<SurfaceSample>& fresh, int frame,
                     StepReport& report);
  /// The safety net of coverage, after the frame's patches are made, faded
  /// and weighed: each of `faces` (those the Poisson update found bare; every
  /// face on the first frame) that no patch covers yet at some point of
  /// `samples` gets a disk at the first such point, chosen greedily in face
  /// order with the Poisson criterion among themselves, and its patch, which
  /// fades in from this frame. A disk that
  /// lost to a nearer new disk whose patch the plane test cut short, or whose
  /// patch could not be built, leaves such faces. A patch covers its own
  /// centre's sample (its coverage tail reaches its border) almost always;
  /// where one does not (a droplet of a torn sheet, as on blender-obstacle),
  /// a face that had a refill disk is not a candidate again, so that it does
  /// not keep rejecting its neighbours' disks. kRefillRounds rounds at most.
  void refill_bare_faces(const SurfaceIndex& surface, const FaceSamples& samples, std::vector<int> faces, int frame,
                         StepReport& report);
  static constexpr int kRefillRounds = 3;
  /// Density and K_t; removes the patches faded out. Returns the faces of
  /// `surface` within reach of the removed sinking patches (Sink::Fade),
  /// which the Poisson update counted as covered.
  std::vector<int> fade(const SurfaceIndex& surface, const SurfaceChange* change, StepReport& report);
  void weigh(StepReport& report);
  /// Where the step from the previous surface to `surface` makes and
  /// destroys surface (measure_surface_change at radius d).
  SurfaceChange measure_change(const SurfaceIndex& surface, double dt, int frame, StepReport& report) const;
  /// Sink::Fade: adds the step's change at each live patch's centre to its
  /// decaying sum (Patch::sunk).
  void track_sinking(const SurfaceChange& change, int frame);
  /// The step's ChangeTally, at the end of the step.
  void tally_change(const SurfaceIndex& surface, const SurfaceChange& change, StepReport& report) const;

  TrackerSettings settings_;
  std::vector<Patch> patches_;
  std::vector<RetiredPatch> retired_;
  std::shared_ptr<const FrameMesh> mesh_;
  std::shared_ptr<const SurfaceIndex> surface_;  // refers to *mesh_
  std::uint32_t next_id_ = 0;
  double step_dt_ = 0.0;  // the current step's dt (Orientation::Flow)
  int frame_ = 0;
  bool started_ = false;
};

/// The removal histogram of one step, as named counts: `retired_<cause>` for
/// every cause (see RetireCause) and `retired_age_<bucket>` for every age
/// bucket (see age_bucket_name), in that order, zeros included.
std::vector<std::pair<std::string, double>> retired_counts(const std::vector<RetiredPatch>& retired);
/// The recuts of one step by the rule that would have retired the patch, as
/// named counts `recut_<cause>` (every cause a recut can follow).
std::vector<std::pair<std::string, double>> recut_counts(const StepReport& step);

/// Counts of patches per state.
PatchCounts count_states(const std::vector<Patch>& patches);

/// A cheap fingerprint of a mesh (counts and a hash of its data) stored in the
/// state file so that a resume on different input is caught.
std::uint64_t mesh_fingerprint(const FrameMesh& mesh);

}  // namespace fluidtex
