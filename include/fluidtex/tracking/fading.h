/// @file fading.h
/// @brief The four disk states and the temporal weight K_t (Gagnon et al.
/// 2019, Sec. 5.4 and 6.3; Yu et al. 2011, Eq. 5).
///
/// Eq. 6 (density-based): fade-in K_t = min(1, t(ρ+1)/τ), fade-out
/// K_t = max(0, 1 − (t − t_k)(ρ+1)/τ). Since ρ changes every frame, K_t is
/// accumulated: K_t += (ρ+1)/τ per frame while fading in, −= while fading out
/// (Eq. 6 with the current density; keeps K_t continuous). Eq. 5 (linear) is
/// the same with ρ = 0. The first step happens on the frame a patch is
/// created (or flagged), so a new patch contributes at once.
#pragma once

#include <cstdint>

#include "fluidtex/tracking/options.h"
#include "fluidtex/util/enum_names.h"

namespace fluidtex {

enum class DiskState : std::uint8_t {
  FadingIn = 0,
  Active = 1,
  FadingOutDistorted = 2,
  FadingOutClose = 3,
};

inline constexpr EnumName<DiskState> kDiskStateNames[] = {{DiskState::FadingIn, "fading_in"},
                                                          {DiskState::Active, "active"},
                                                          {DiskState::FadingOutDistorted, "fading_out_distorted"},
                                                          {DiskState::FadingOutClose, "fading_out_close"}};
constexpr const auto& enum_names(DiskState) { return kDiskStateNames; }
inline const char* to_string(DiskState s) { return enum_name(s); }

/// Why a patch started leaving the distribution (the rule that fired). Under
/// the patch-scale distortion test (DistortionTest::Patch) VerticesLost,
/// Split, Flipped and Quality name the largest share of the disk's weight
/// lost that way when the disk as a whole shows too little.
enum class RetireCause : std::uint8_t {
  None = 0,
  CentreLost,    ///< the disk centre moved farther than mpt from the new surface (removed at once)
  Emptied,       ///< every patch triangle was removed in advection (removed at once)
  VerticesLost,  ///< vertices inside the disk moved beyond mpt (fades out as distorted)
  Split,         ///< a triangle inside the disk spans two surface components
  Flipped,       ///< a triangle inside the disk turned against the surface normal
  Quality,       ///< stretched: Q_V < Q_vmin at a vertex inside the disk, or too low over the disk
  TooClose,      ///< within the kill distance of an older disk (fades out as too close)
  Sunk,          ///< the surface around it was destroyed (Sink::Fade; fades out as too close)
  Outflow,       ///< the centre left through an open rim, an outflow (fades out on the rim)
};
constexpr int kRetireCauses = 10;
inline constexpr EnumName<RetireCause> kRetireCauseNames[] = {
    {RetireCause::None, "none"},       {RetireCause::CentreLost, "centre_lost"},
    {RetireCause::Emptied, "emptied"}, {RetireCause::VerticesLost, "vertices_lost"},
    {RetireCause::Split, "split"},     {RetireCause::Flipped, "flipped"},
    {RetireCause::Quality, "quality"}, {RetireCause::TooClose, "too_close"},
    {RetireCause::Sunk, "sunk"},       {RetireCause::Outflow, "outflow"}};
constexpr const auto& enum_names(RetireCause) { return kRetireCauseNames; }
inline const char* to_string(RetireCause c) { return enum_name(c); }

/// Age buckets (frames since creation when the rule fired) of the removal
/// histogram: [0,1], [2,3], [4,7], [8,15], [16,31], [32,∞).
constexpr int kAgeBuckets = 6;
int age_bucket(int age);
const char* age_bucket_name(int bucket);
inline bool is_fading_out(DiskState s) { return s == DiskState::FadingOutDistorted || s == DiskState::FadingOutClose; }

struct FadeResult {
  DiskState state;
  double kt;
  bool remove;  ///< K_t reached 0 (or below) while fading out
};

/// How much K_t changes in one frame for a disk of density `rho` whose
/// centre moved `motion` (units of d): Eq. 6's (ρ + 1)/τ, Eq. 5's 1/τ, or
/// for Fading::Flow the larger of Eq. 6's and `motion`.
double fade_rate(int rho, int fade_frames, Fading fading, double motion);

/// One frame of fading for a disk in `state` with weight `kt` and density
/// `rho` (other disks in the same plane within radius d, any state);
/// `motion` is how far its centre moved this frame, in units of d
/// (Fading::Flow); K_t changes by at least `at_least` (a sunk patch: the
/// surface around it going, Sink::Fade).
FadeResult fade_step(DiskState state, double kt, int rho, int fade_frames, Fading fading, double motion = 0.0,
                     double at_least = 0.0);

}  // namespace fluidtex
