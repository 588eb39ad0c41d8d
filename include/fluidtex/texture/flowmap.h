/// @file flowmap.h
/// @brief The baseline artists use today: two-phase advected UVs ("flow
/// map" texturing), run with `fluidtex run --method flowmap` so that the
/// same evaluation can be made on both methods.
///
/// Every vertex of the current frame carries two uv sets, phase A and phase
/// B. Meshes change topology every frame, so the uvs are carried
/// semi-Lagrangian: a vertex x of frame t+1 with velocity v is traced back
/// to x − v·dt, projected onto frame t's surface (closest point), and takes
/// the barycentric blend of frame t's vertex uvs there; a point traced back
/// beyond the rim of an open surface (inflow) extends the field past the rim
/// with the rest gradient (no streaks at inflow boundaries). Each phase is reset
/// to the rest parameterisation every N frames (`--flowmap-period`), phase B
/// half a period after A: the planar projection of the position onto the
/// plane perpendicular to `--flowmap-axis`, divided by the tile size
/// T = (2 + β)·d of the patch method (so both show the texture at the same
/// scale). Linear functions survive the transport exactly, so on a uniform
/// flow the texture moves with it: uv(x, t) = rest(x − v·t).
///
/// Blending: w_A = sin²(π φ_A), w_B = sin²(π φ_B), φ = the phase's age / N
/// (0 at its reset, so a phase is invisible when it jumps back), normalised
/// to w_A + w_B = 1 (for even N that is w_B = 1 − w_A exactly). Per texel,
/// both uvs are interpolated at the texel's surface point, looked up in the
/// exemplar (bilinear, wrapping, at anchor + s·uv with a random tile anchor
/// per phase and cycle) and blended with Eq. 7 or linearly, as the patch
/// method does (synthesis.h); results are clamped and gutters dilated.
///
/// Parallel (oneTBB) over vertices and atlas tiles; every loop writes only
/// its own slots and the anchors are hashes of (seed, phase, cycle), so the
/// result does not depend on the thread count.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fluidtex/geometry/surface.h"
#include "fluidtex/texture/exemplar.h"
#include "fluidtex/texture/synthesis.h"
#include "fluidtex/tracking/options.h"
#include "fluidtex/util/enum_names.h"
#include "fluidtex/util/timing.h"

namespace fluidtex {

/// How the surface is textured (`--method`).
enum class TexturingMethod {
  Patches,  ///< Gagnon et al. 2019 (the default)
  FlowMap,  ///< two-phase advected UVs (this header)
};

inline constexpr EnumName<TexturingMethod> kTexturingMethodNames[] = {{TexturingMethod::Patches, "patches"},
                                                                      {TexturingMethod::FlowMap, "flowmap"}};
constexpr const auto& enum_names(TexturingMethod) { return kTexturingMethodNames; }
inline const char* to_string(TexturingMethod m) { return enum_name(m); }

struct FlowMapOptions {
  int period = 16;  ///< N: frames between two resets of a phase (>= 2)
  /// The rest uv is the position projected onto the plane perpendicular to
  /// this axis (Axis, tracking/options.h: `--flowmap-axis`). z: the generated scenes are flat in z = 0 or have z up.
  Axis axis = Axis::Z;

  /// Every field as f(OptionInfo, field) (util/options.h).
  template <class Self, class F>
  static void for_each_option(Self& o, F&& f) {
    f(OptionInfo{.name = "flowmap-period",
                 .help = "flowmap: frames between two resets of a uv phase; phase B is offset by half of it",
                 .bounds = at_least(2)},
      o.period);
    f(OptionInfo{.name = "flowmap-axis",
                 .help = "flowmap: rest uv = position projected along this axis (z: the generated scenes' normal "
                         "/ up axis)"},
      o.axis);
  }
  void validate() const;  ///< InputError for a bad value
};

/// The phases' ages (frames since their last reset) at step `step` (0 = the
/// first frame): A resets at steps ≡ 0, B at steps ≡ N/2 (mod N).
std::array<int, 2> phase_ages(int step, int period);
/// The normalised blend weights {w_A, w_B} at `step` (see the file comment).
std::array<double, 2> phase_weights(int step, int period);
/// The rest uv of a point: its coordinates in the plane perpendicular to
/// `axis` ((y, z) for x, (z, x) for y, (x, y) for z) divided by `tile_size`.
Vec2 rest_uv(const Vec3& p, Axis axis, double tile_size);

/// What a frame's synthesis needs: the uv sets of the frame's vertices (in
/// exemplar tiles), the weights, the phases' lookup anchors and the uv scale s.
struct FlowMapFrame {
  std::array<std::vector<Vec2>, 2> uv;
  std::array<double, 2> weight{1.0, 0.0};
  std::array<Vec2, 2> anchor{Vec2::Zero(), Vec2::Zero()};
  double uv_scale = 1.0;
};

struct FlowMapSettings {
  FlowMapOptions flowmap;
  /// Radius d and margin β set the tile size (2 + β)·d; s the uv scale. The
  /// automatic radius is resolved on the first frame as the tracker does.
  TrackingOptions tracking;
  /// The tile size instead of (2 + β)·d (the job's --exemplar-size).
  std::optional<double> exemplar_size;
  std::uint64_t seed = 1;
};

struct FlowMapStep {
  int step = 0;                             ///< 0 on the first frame
  std::array<bool, 2> reset{false, false};  ///< phases reset this frame
  StageSeconds seconds;                     ///< per stage
};

/// Carries the two uv sets from frame to frame.
class FlowMapAdvector {
 public:
  explicit FlowMapAdvector(FlowMapSettings settings);

  /// Advances to `mesh` (`dt` seconds after the previous step; ignored on
  /// the first): back-traces every vertex into the previous frame, then
  /// resets the phases whose age is 0. The first frame starts both phases
  /// at rest. The advector keeps the mesh for the next step.
  FlowMapStep step(std::shared_ptr<const FrameMesh> mesh, double dt);

  /// Per vertex of the current mesh, the uvs of phase 0 (A) or 1 (B).
  const std::vector<Vec2>& uv(int phase) const { return uv_[phase]; }
  /// A copy of what the current frame's synthesis needs.
  FlowMapFrame frame() const;
  /// The parameters in use; lengths are resolved after the first step.
  const FlowMapSettings& settings() const { return settings_; }
  /// Scene units per exemplar tile at s = 1: exemplar_size, else (2 + β)·d
  /// (after the first step).
  double tile_size() const { return tile_size_; }
  /// The current surface, shared (stays valid after later steps).
  std::shared_ptr<const SurfaceIndex> shared_surface() const { return surface_; }
  int steps() const { return steps_; }

 private:
  FlowMapSettings settings_;
  std::shared_ptr<const FrameMesh> mesh_;
  std::shared_ptr<const SurfaceIndex> surface_;  // refers to *mesh_
  std::array<std::vector<Vec2>, 2> uv_;
  std::array<int, 2> cycle_{0, 0};  // resets so far per phase (anchor stream)
  double tile_size_ = 0.0;
  int steps_ = 0;
};

/// Synthesises the atlas from the two phases (colour, and with `aov`: Σw = 1,
/// the number of phases with w > 0, and the dominant phase as a colour).
SynthesisResult synthesize_flowmap(const SurfaceIndex& surface, const Atlas& atlas, const TexelMap& map,
                                   const FlowMapFrame& frame, const Exemplar& exemplar, Blend blend, bool aov = false);

}  // namespace fluidtex
