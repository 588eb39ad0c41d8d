#include "fluidtex/fading.h"

namespace fluidtex {

const char* to_string(DiskState s) {
  switch (s) {
    case DiskState::FadingIn: return "fading_in";
    case DiskState::Active: return "active";
    case DiskState::FadingOutDistorted: return "fading_out_distorted";
    case DiskState::FadingOutClose: return "fading_out_close";
  }
  return "?";
}

FadeResult fade_step(DiskState state, double kt, int rho, int fade_frames, Fading fading) {
  const double rate = (fading == Fading::Density ? static_cast<double>(rho) + 1.0 : 1.0) /
                      static_cast<double>(fade_frames);
  switch (state) {
    case DiskState::FadingIn:
      kt += rate;  // Eq. 6, first line
      // Within rounding of 1 counts as 1: τ steps of 1/τ must reach it.
      if (kt >= 1.0 - 1e-9) return {DiskState::Active, 1.0, false};
      return {DiskState::FadingIn, kt, false};
    case DiskState::Active:
      return {DiskState::Active, 1.0, false};
    case DiskState::FadingOutDistorted:
    case DiskState::FadingOutClose:
      kt -= rate;  // Eq. 6, last line; K_t <= 0 removes the patch at once
      if (kt <= 1e-9) return {state, 0.0, true};
      return {state, kt, false};
  }
  return {state, kt, false};
}

}  // namespace fluidtex
