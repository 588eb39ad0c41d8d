/// @file surface_change.h
/// @brief Where the liquid makes and destroys surface between two frames:
/// the instrument behind "patches pile up here".
///
/// A closed tank keeps its surface: what the flow squeezes in one place it
/// stretches in another. An inflow, a jet leaving its nozzle or a sheet
/// tearing open makes new surface that no earlier surface is carried to; an
/// outflow, a jet plunging into a pool or two sheets merging destroys
/// surface, and whatever was carried there (patches) is squeezed into less
/// and less area. Neither shows in the velocities alone (an outflow's end
/// face is still while the liquid crosses it), so the change is measured as
/// the advection sees it: every face of the previous frame is carried by its
/// velocity over the step (as the patches are: x + v·dt, projected onto the
/// next surface) and deposits its area where it lands. Around each face of
/// the next frame, within the disk radius d and in the same plane (the
/// Poisson plane test), the change is
///
///     ln(area of the next surface there / area carried there),
///
/// 0 where the surface is kept, positive where surface is made (nothing or
/// little arrives: a source), negative where it is destroyed (more arrives
/// than there is: a sink). It is the log of the local area ratio over the
/// step, at the scale a patch sees.
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "fluidtex/geometry/surface.h"

namespace fluidtex {

/// The change per face of the next frame (see the file comment), per frame
/// step: ln of the area ratio divided by the number of frames the step spans
/// (1 between consecutive frames). Clamped to ±kMaxSurfaceChange.
struct SurfaceChange {
  std::vector<float> rate;
  /// The change at a point of the next surface (its face's); 0 for an invalid point.
  double at(const SurfacePoint& p) const { return p.valid() ? rate[p.face] : 0.0; }
};

/// |ln area ratio| is clamped here: e³ ≈ 20 times more or less area, where a
/// ball received (almost) nothing or a pile of surface.
inline constexpr double kMaxSurfaceChange = 3.0;

/// Measures the change from `previous` (whose vertex velocities carry it) to
/// `next` over `dt` seconds, spanning `frames` frame steps, at radius
/// `radius` with the plane test `plane_angle` (N·N' > pa). Deterministic and
/// thread-count independent (TBB over faces, each writing its own slot).
SurfaceChange measure_surface_change(const SurfaceIndex& previous, const SurfaceIndex& next, double dt, double frames,
                                     double radius, double plane_angle);

/// The classes `stats.jsonl` counts by: where the surface
/// shrinks fast, shrinks, is kept, grows, grows fast. The edges are area
/// changes per frame (ln ratio): ±1 % is within the velocity noise of real
/// caches, ±5 % a frame halves or doubles the area in 14 frames, less than
/// the kill wait and a fade together.
inline constexpr int kChangeClasses = 5;
inline constexpr std::array<double, kChangeClasses - 1> kChangeClassEdges = {-0.05, -0.01, 0.01, 0.05};
/// "sink_fast", "sink", "kept", "source", "source_fast".
const char* change_class_name(int c);
/// The class of a change per frame.
int change_class(double rate);

/// Per class: the next surface's area, the patches (in any state) whose
/// centre lies there, and the births and removals of the step there.
struct ChangeTally {
  std::array<double, kChangeClasses> area{};
  std::array<int, kChangeClasses> patches{}, births{}, removals{};
  /// The surface made and destroyed over the step: Σ area × (1 − e^−rate)
  /// over the faces that gained area, Σ area × (e^−rate − 1) over those that
  /// lost it (the area carried there that is no longer surface). At a
  /// constant patch count per area, `made` over the whole area is the least
  /// share of the patches that new disks (or growing patches) must supply
  /// per step.
  double made = 0.0, lost = 0.0;
  /// False on a first frame (no previous surface) and on an empty one.
  bool measured() const {
    for (double a : area)
      if (a > 0.0) return true;
    return false;
  }
  /// As stats.jsonl keys: `change_area_<class>`, `change_patches_<class>`,
  /// `change_births_<class>`, `change_removals_<class>`, in that order, then
  /// `change_made_area` and `change_lost_area`.
  std::vector<std::pair<std::string, double>> named() const;
};

/// The tally of `change` (measured onto `surface`): the surface's area, the
/// patch centres `centres`, and the births and removals (points, taken to
/// the surface point nearest each), by class.
ChangeTally tally_change(const SurfaceIndex& surface, const SurfaceChange& change,
                         const std::vector<SurfacePoint>& centres, const std::vector<Vec3>& births,
                         const std::vector<Vec3>& removals);

}  // namespace fluidtex
