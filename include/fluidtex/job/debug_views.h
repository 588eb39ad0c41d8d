/// @file debug_views.h
/// @brief `--debug-views`: per-frame PLYs a person can open in any mesh
/// viewer to inspect the distribution, as in Gagnon et al. 2019, Fig. 2:
///  - patches: every patch's current triangles, coloured by patch id (Fig. 2b);
///  - disks: the disk centres coloured by state (Fig. 2c): green kept (active
///    or fading in), red removed (fading out), blue added this frame.
#pragma once

#include <string>
#include <vector>

#include "fluidtex/tracking/patch.h"

namespace fluidtex {

void write_patch_view(const std::string& path, const std::vector<Patch>& patches);
void write_disk_view(const std::string& path, const std::vector<Patch>& patches, int frame);

}  // namespace fluidtex
