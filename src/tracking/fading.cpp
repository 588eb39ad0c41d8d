#include "fluidtex/tracking/fading.h"

#include <algorithm>

namespace fluidtex {

int age_bucket(int age) {
  int b = 0;
  for (int limit = 2; b < kAgeBuckets - 1 && age >= limit; limit *= 2) ++b;
  return b;
}

const char* age_bucket_name(int bucket) {
  static const char* names[kAgeBuckets] = {"0_1", "2_3", "4_7", "8_15", "16_31", "32_up"};
  return names[bucket];
}

double fade_rate(int rho, int fade_frames, Fading fading, double motion) {
  const double density = (static_cast<double>(rho) + 1.0) / static_cast<double>(fade_frames);  // Eq. 6
  switch (fading) {
    case Fading::Flow: return std::max(density, motion);
    case Fading::Density: return density;
    case Fading::Linear: return 1.0 / static_cast<double>(fade_frames);  // Eq. 5
  }
  return density;
}

FadeResult fade_step(DiskState state, double kt, int rho, int fade_frames, Fading fading, double motion,
                     double at_least) {
  const double rate = std::max(fade_rate(rho, fade_frames, fading, motion), at_least);
  switch (state) {
    case DiskState::FadingIn:
      kt += rate;  // Eq. 6, first line
      // Within rounding of 1 counts as 1: τ steps of 1/τ must reach it.
      if (kt >= 1.0 - 1e-9) return {DiskState::Active, 1.0, false};
      return {DiskState::FadingIn, kt, false};
    case DiskState::Active: return {DiskState::Active, 1.0, false};
    case DiskState::FadingOutDistorted:
    case DiskState::FadingOutClose:
      kt -= rate;  // Eq. 6, last line; K_t <= 0 removes the patch at once
      if (kt <= 1e-9) return {state, 0.0, true};
      return {state, kt, false};
  }
  return {state, kt, false};
}

}  // namespace fluidtex
