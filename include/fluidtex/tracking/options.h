/// @file options.h
/// @brief Parameters of the method (Gagnon et al. 2019, Appendix A, Tables 3
/// and 4) and of the job, each with its default (docs/method.md, Definitions). These
/// structs are the single source of truth: the command line, `--help`, the
/// config file, `--print-config` and the state file's settings are generated
/// from `for_each_option` (util/options.h).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "fluidtex/util/enum_names.h"
#include "fluidtex/util/options.h"

namespace fluidtex {

/// Poisson-disk rejection criterion (Sec. 4, Figs. 3, 5).
enum class Criterion {
  Ellipsoid,  ///< the paper's: plane test AND k-criterion (Eq. 1)
  Sphere,     ///< plain 3D distance < d (Fig. 3a), for ablations
  Plane,      ///< plane test AND 3D distance < d (Fig. 3b), for ablations
};

/// Temporal weight K_t (Sec. 6.3).
enum class Fading {
  /// The default (the paper's future work, Sec. 8): Eq. 6, and at least as
  /// fast as the flow carries the patch across its radius: the rate per
  /// frame is max((ρ + 1)/τ, |Δp|/d), Δp the disk centre's motion in the
  /// frame. Where the liquid moves, a fade is done before the flow has carried
  /// the patch one radius, so it reads as the texture moving rather than
  /// changing; still liquid fades as Eq. 6 says.
  Flow,
  Density,  ///< Eq. 6: fades faster where more disks overlap (the paper's)
  Linear,   ///< Eq. 5, Yu et al. 2011: fixed τ frames
};

/// Where "too distorted" (Sec. 5.3) is judged.
enum class DistortionTest {
  /// The default (departure from the paper's per-vertex rule): the patch
  /// is too distorted when its quality at the scale it is seen, the mean of
  /// Q_T over the triangles inside the disk weighted by rest area and by the
  /// radial term of K_S, falls below Q_vmin. Reconstructed surfaces and
  /// their re-projection make single triangles spike while the patch as a
  /// whole is fine; Q_V still scales each vertex's weight (Eq. 4), so a
  /// locally poor spot fades under its neighbours instead of killing the patch.
  Patch,
  Vertex,  ///< any vertex inside the disk with Q_V < Q_vmin (Yu et al. 2011)
};

/// What becomes of a patch found too distorted (Sec. 5.3).
enum class Distorted {
  /// The default (departure from the paper): the patch is cut again around
  /// its own centre from the current surface and flattened anew, its uv
  /// turned and its texture shifted to match what it showed
  /// (recut_patch), so it keeps its place, its fading state and its
  /// texture instead of fading out and being replaced by a new patch.
  Recut,
  Fade,  ///< it fades out and the Poisson update replaces it (the paper)
};

/// Where the Poisson update measures a gap for a new disk after the first
/// frame (Sec. 5.4, with the birth margin γ).
enum class BirthGap {
  /// The default (departure from the paper): a candidate is rejected within
  /// (1 + γ)·d of an existing disk's centre in space, and also within
  /// (1 + γ)·d of the centre of a live patch that covers it, measured in
  /// that patch's uv. A patch the liquid stretches still shows its own disk
  /// where its centre has moved away, so that gap seeds nothing until the
  /// patch yields (relax-frames) or is recut, and a stretch the liquid
  /// undoes leaves no extra disks behind.
  Patches,
  Centres,  ///< from the disk centres in space only (the paper's dart throwing)
};

/// What becomes of a pair of patches within the kill distance where the
/// liquid destroys the surface around them.
enum class Sink {
  /// The one the kill distance flags (the younger, Sec. 5.4) fades out at
  /// once (cause "sunk"), without the kill-frames wait, when the surface
  /// around its centre has lost the fraction α of its area (the kill
  /// distance's α) over about the last kill-frames frames: the change
  /// measured each frame at radius d (surface_change.h), summed with
  /// weights decaying by 1 − 1/kill-frames a frame. The wait exists for
  /// pairs that part again (surface squeezed by a passing wave and stretched
  /// after it); where the surface they stand on is being destroyed (an
  /// outflow, a jet plunging into a pool, sheets merging) they do not, and
  /// each frame of waiting stacks another pair there. It fades at least as
  /// fast as that surface goes: K_t falls each frame by at least the
  /// surface's loss rate there over −ln(1 − α), so it is gone by the time
  /// the surface around it has lost another α of its area. While it fades,
  /// a sunk patch still counts as cover and as a disk, so no new disk is
  /// seeded on the surface that is going; the faces it leaves bare are
  /// refilled when it is gone.
  Fade,
  Keep,  ///< the kill-frames wait everywhere (the paper)
};

/// What covers surface left bare close to a live disk (coverage check on).
enum class GapFill {
  /// The disk's own patch, cut again around its centre from the current
  /// surface (recut_patch: its texture kept in place, the new part fading
  /// in): surface left bare within d of a live disk's centre, as where
  /// liquid enters next to a patch (an inflow, a jet leaving its nozzle),
  /// is the surface that disk stands for. A new disk there would sit within
  /// the kill distance of it and, carried along with it, stay.
  Recut,
  Seed,  ///< a new disk on the bare surface, however close to a live one
};

/// Which way a new patch shows its exemplar (orientation.h).
enum class Orientation {
  /// The default (departure from the paper): as the live patches it
  /// overlaps show theirs, or along --orientation-axis where it overlaps
  /// none, so the exemplar keeps one direction across the surface and turns
  /// only as the liquid turns it.
  Field,
  /// Along the surface velocity over its disk where that moves at least
  /// kFlowOrientationMotion disk radii a frame (streaks that follow the
  /// flow); as Field where it is slower.
  Flow,
  Random,  ///< as LSCM leaves its chart: an arbitrary angle per patch (the paper)
};

/// A world axis: the direction of a patch's u where it overlaps no live
/// patch (--orientation-axis), the flow map's projection axis (--flowmap-axis).
enum class Axis { X, Y, Z };

inline constexpr EnumName<Criterion> kCriterionNames[] = {
    {Criterion::Ellipsoid, "ellipsoid"}, {Criterion::Sphere, "sphere"}, {Criterion::Plane, "plane"}};
constexpr const auto& enum_names(Criterion) { return kCriterionNames; }
inline const char* to_string(Criterion c) { return enum_name(c); }
inline constexpr EnumName<Fading> kFadingNames[] = {
    {Fading::Flow, "flow"}, {Fading::Density, "density"}, {Fading::Linear, "linear"}};
constexpr const auto& enum_names(Fading) { return kFadingNames; }
inline const char* to_string(Fading f) { return enum_name(f); }
inline constexpr EnumName<DistortionTest> kDistortionTestNames[] = {{DistortionTest::Patch, "patch"},
                                                                    {DistortionTest::Vertex, "vertex"}};
constexpr const auto& enum_names(DistortionTest) { return kDistortionTestNames; }
inline const char* to_string(DistortionTest t) { return enum_name(t); }
inline constexpr EnumName<Distorted> kDistortedNames[] = {{Distorted::Recut, "recut"}, {Distorted::Fade, "fade"}};
constexpr const auto& enum_names(Distorted) { return kDistortedNames; }
inline const char* to_string(Distorted d) { return enum_name(d); }
inline constexpr EnumName<BirthGap> kBirthGapNames[] = {{BirthGap::Patches, "patches"}, {BirthGap::Centres, "centres"}};
constexpr const auto& enum_names(BirthGap) { return kBirthGapNames; }
inline const char* to_string(BirthGap g) { return enum_name(g); }
inline constexpr EnumName<GapFill> kGapFillNames[] = {{GapFill::Recut, "recut"}, {GapFill::Seed, "seed"}};
constexpr const auto& enum_names(GapFill) { return kGapFillNames; }
inline const char* to_string(GapFill g) { return enum_name(g); }
inline constexpr EnumName<Orientation> kOrientationNames[] = {
    {Orientation::Field, "field"}, {Orientation::Flow, "flow"}, {Orientation::Random, "random"}};
constexpr const auto& enum_names(Orientation) { return kOrientationNames; }
inline const char* to_string(Orientation o) { return enum_name(o); }
inline constexpr EnumName<Axis> kAxisNames[] = {{Axis::X, "x"}, {Axis::Y, "y"}, {Axis::Z, "z"}};
constexpr const auto& enum_names(Axis) { return kAxisNames; }
inline const char* to_string(Axis a) { return enum_name(a); }
inline constexpr EnumName<Sink> kSinkNames[] = {{Sink::Fade, "fade"}, {Sink::Keep, "keep"}};
constexpr const auto& enum_names(Sink) { return kSinkNames; }
inline const char* to_string(Sink k) { return enum_name(k); }

/// Tracking parameters (Tables 3 and 4). Lengths in scene units; the three
/// lengths left unset are derived from the first frame (resolved()).
struct TrackingOptions {
  std::optional<double> radius;          ///< d: Poisson disk radius; unset = 0.05 × first frame's bbox diagonal
  double plane_angle = 0.5;              ///< pa: "same plane" when N_c·N > pa
  double patch_vertex_angle = 0.5;       ///< pva: patch triangles need N_T·N > pva
  double max_distortion = 3.0;           ///< δmax: Sorkine distortion at which Q_T = 0
  double uv_scale = 1.0;                 ///< s: uv scale applied at exemplar lookup
  std::optional<double> max_projection;  ///< mpt: max distance to re-project a vertex; unset = 0.25 × d
  int fade_frames = 32;                  ///< τ: fading period in frames (docs/method.md)
  std::optional<double> thickness;       ///< cs: ellipsoid half-thickness along N; unset = 0.25 × d
  double kill_alpha = 0.25;              ///< α: kill distance is (1 − α)·d (Table 4)
  double min_vertex_quality = 0.5;       ///< Q_vmin: a vertex below this distorts its patch (Table 4)
  double selection_margin = 0.6;         ///< β: patch triangles are taken within (1 + β)·d of the centre
  int relax_frames =
      8;                ///< plastic patches: stretch beyond the yield relaxes over this many frames (0: off, the paper)
  int kill_frames = 8;  ///< a disk too close to an older one fades out after this many frames in a row (0: at once)
  double birth_margin = 0.15;  ///< γ: new disks keep (1 + γ)·d from the others after the first frame (0: the paper)
  double projection_slack =
      0.5;  ///< κ: a point may land up to mpt + κ·|its advected normal motion| off the new surface (0: the paper)
  Criterion criterion = Criterion::Ellipsoid;
  Fading fading = Fading::Flow;
  DistortionTest distortion_test = DistortionTest::Patch;
  Distorted distorted = Distorted::Recut;
  BirthGap birth_gap = BirthGap::Patches;
  GapFill gap_fill = GapFill::Recut;
  Sink sink = Sink::Fade;
  Orientation orientation = Orientation::Field;
  Axis orientation_axis = Axis::X;

  /// Every field as f(OptionInfo, field), in the order of --help, the config
  /// file and the state file's settings block (util/options.h).
  template <class Self, class F>
  static void for_each_option(Self& o, F&& f) {
    for_each_paper_option(o, f);
    for_each_rule_option(o, f);
  }
  /// The paper's parameters (Tables 3 and 4), then the rules and lengths
  /// that depart from it (each names the paper's setting).
  template <class Self, class F>
  static void for_each_paper_option(Self& o, F&& f);
  template <class Self, class F>
  static void for_each_rule_option(Self& o, F&& f);

  /// Throws InputError naming the option for an out-of-range value.
  void validate() const;
  /// A copy with the automatic lengths filled in from the first frame's
  /// bounding-box diagonal.
  TrackingOptions resolved(double first_frame_diagonal) const;
  /// The resolved lengths: InternalError when resolved() has not filled them.
  double d() const { return length(radius, "radius"); }
  double mpt() const { return length(max_projection, "max-projection"); }
  double cs() const { return length(thickness, "thickness"); }
  /// Scene units one exemplar tile spans at s = 1: `given` (the job's
  /// --exemplar-size) when set, else (2 + β)·d, so a patch's disk shows
  /// most of a tile, each patch a different part of it. A tile spans
  /// exemplar_tile_size() / s on the surface.
  double exemplar_tile_size(const std::optional<double>& given = std::nullopt) const {
    return given ? *given : (2.0 + selection_margin) * d();
  }
  /// Plastic patches' yield: the Sorkine distortion up to which a triangle
  /// keeps its uv (relax-frames), where its quality Q_T is halfway between 1
  /// and Q_vmin (1.5 with the defaults), so a patch relaxes before the
  /// distortion test could retire it.
  double relax_yield() const { return max_distortion - (max_distortion - 1.0) * (1.0 + min_vertex_quality) / 2.0; }

 private:
  static double length(const std::optional<double>& v, const char* name);
};

template <class Self, class F>
void TrackingOptions::for_each_paper_option(Self& o, F&& f) {
  f(OptionInfo{.name = "radius",
               .help = "d: Poisson disk radius in scene units (auto: 0.05 x first frame's bounding-box diagonal)",
               .bounds = above(0)},
    o.radius);
  f(OptionInfo{.name = "plane-angle",
               .help = "pa: disks are in the same plane when the dot product of their normals exceeds this",
               .bounds = between(-1, 1, false, true)},
    o.plane_angle);
  f(OptionInfo{.name = "patch-vertex-angle",
               .help = "pva: a patch keeps only triangles whose normal dot the disk normal exceeds this",
               .bounds = between(-1, 1, false, true)},
    o.patch_vertex_angle);
  f(OptionInfo{.name = "max-distortion",
               .help = "delta_max: Sorkine distortion at which a triangle's quality reaches 0",
               .bounds = above(1)},
    o.max_distortion);
  f(OptionInfo{.name = "uv-scale",
               .help = "s: scale of the uv coordinates at exemplar lookup (larger = smaller texture features)",
               .bounds = between(0, 1e6, true, false)},
    o.uv_scale);
  f(OptionInfo{.name = "max-projection",
               .help = "mpt: patch vertices farther than this from the new surface are removed (auto: 0.25 x radius)",
               .bounds = above(0)},
    o.max_projection);
  f(OptionInfo{.name = "fade-frames", .help = "tau: fading period in frames", .bounds = at_least(1)}, o.fade_frames);
  f(OptionInfo{.name = "thickness",
               .help = "cs: ellipsoid half-thickness along the normal, below the smallest detail (auto: 0.25 x radius)",
               .bounds = above(0)},
    o.thickness);
  f(OptionInfo{.name = "kill-alpha",
               .help = "alpha: disks closer than (1 - alpha) x radius are faded out (Table 4)",
               .bounds = between(0, 1, false, true)},
    o.kill_alpha);
  f(OptionInfo{.name = "min-vertex-quality",
               .help = "Q_vmin: a patch with a vertex quality below this fades out (Table 4)",
               .bounds = between(0, 1)},
    o.min_vertex_quality);
  f(OptionInfo{.name = "selection-margin",
               .help = "beta: patch triangles are selected within (1 + beta) x radius of the disk centre",
               .bounds = at_least(0)},
    o.selection_margin);
}

template <class Self, class F>
void TrackingOptions::for_each_rule_option(Self& o, F&& f) {
  f(OptionInfo{.name = "relax-frames",
               .help = "plastic patches: a triangle stretched beyond the yield gives way by 1/N of the excess a frame "
                       "(0: off, the paper)",
               .bounds = at_least(0)},
    o.relax_frames);
  f(OptionInfo{.name = "kill-frames",
               .help = "frames a too-close disk waits before it fades out, so that compressions the liquid undoes "
                       "retire nothing (0: the paper)",
               .bounds = at_least(0)},
    o.kill_frames);
  f(OptionInfo{.name = "birth-margin",
               .help = "gamma: after the first frame a disk is born only where none lies within (1 + gamma) x radius "
                       "(0: the paper)",
               .bounds = between(0, 1)},
    o.birth_margin);
  f(OptionInfo{.name = "projection-slack",
               .help = "kappa: a vertex is kept within mpt + kappa x its motion along the normal from the new surface "
                       "(0: the paper)",
               .bounds = between(0, 4)},
    o.projection_slack);
  f(OptionInfo{.name = "criterion", .help = "Poisson rejection: ellipsoid (paper), sphere, plane"}, o.criterion);
  f(OptionInfo{.name = "fading",
               .help = "Temporal weight: flow (Eq. 6, at least as fast as the flow carries a patch across its "
                       "radius), density (Eq. 6, paper) or linear (Eq. 5)"},
    o.fading);
  f(OptionInfo{.name = "distortion-test",
               .help = "patch: too distorted when the disk's mean quality is below Q_vmin; vertex: when any vertex's "
                       "is (the paper)"},
    o.distortion_test);
  f(OptionInfo{.name = "distorted",
               .help = "a too-distorted patch: recut (cut again in place, texture kept) or fade (replaced by a new "
                       "one, the paper)"},
    o.distorted);
  f(OptionInfo{.name = "birth-gap",
               .help = "where a new disk's gap is measured: patches (in space and in the uv of the live patches) or "
                       "centres (the paper)"},
    o.birth_gap);
  f(OptionInfo{.name = "gap-fill",
               .help =
                   "bare surface within radius of a disk: recut (that disk's patch cut again) or seed (a new disk)"},
    o.gap_fill);
  f(OptionInfo{.name = "sink",
               .help = "where liquid destroys surface: fade (a too-close disk there goes at once) or keep (the "
                       "kill-frames wait, the paper)"},
    o.sink);
  f(OptionInfo{.name = "orientation",
               .help = "which way a new patch shows the exemplar: field (as the patches it overlaps, else along "
                       "--orientation-axis), flow (along the surface velocity where it is fast) or random (the paper)"},
    o.orientation);
  f(OptionInfo{.name = "orientation-axis",
               .help = "the world axis the exemplar's u follows where a new patch overlaps none (the next axis where "
                       "the surface faces it)"},
    o.orientation_axis);
}

}  // namespace fluidtex
