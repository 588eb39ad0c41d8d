/// @file patch_counts.h
/// @brief How many patches a frame has in each of the four disk states
/// (fading in, active, fading out because distorted, fading out because too
/// close to another disk).
#pragma once

namespace fluidtex {

struct PatchCounts {
  int fading_in = 0;
  int active = 0;
  int fading_out_distorted = 0;
  int fading_out_close = 0;
  int total() const { return fading_in + active + fading_out_distorted + fading_out_close; }
};

}  // namespace fluidtex
