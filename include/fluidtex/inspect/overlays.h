/// @file overlays.h
/// @brief Diagnostic overlays drawn over a rendered frame (`fluidtex preview
/// --overlay`), depth-tested against the render's G-buffer:
///  - borders: the boundary edges of every live patch (edges used by exactly
///    one patch triangle), one colour per patch id (id_color);
///  - states: every patch's disk centre as a filled circle coloured by its
///    state, as in Gagnon et al. 2019, Fig. 2 b/c (state_color);
///  - velocity: arrows of the input mesh's vertex velocities, one per cell of
///    a screen grid (the visible vertex nearest the cell centre), v·dt·k long.
#pragma once

#include <string>
#include <vector>

#include "fluidtex/geometry/mesh.h"
#include "fluidtex/inspect/render.h"
#include "fluidtex/tracking/fading.h"
#include "fluidtex/tracking/patch.h"

namespace fluidtex {

/// The 8-bit sRGB colour of a disk state: fading in blue, active green,
/// fading out (too distorted) red, fading out (too close) yellow.
std::array<unsigned char, 3> state_color(DiskState state);

/// A depth bias suited to a scene: 0.5% of the bounding-box diagonal of
/// `positions` (at least 1e-9).
double default_depth_bias(const std::vector<Vec3>& positions);

/// Boundary edges of each patch in its id colour.
void draw_patch_borders(Canvas& canvas, const std::vector<Patch>& patches);

/// Disk centres as discs of `radius` pixels coloured by state.
void draw_disk_states(Canvas& canvas, const std::vector<Patch>& patches, double radius);

/// Velocity arrows (white) of `mesh`'s vertices, at most one per `spacing` ×
/// `spacing` pixel cell, from p to p + v·`scale` (scale = dt·k).
void draw_velocities(Canvas& canvas, const FrameMesh& mesh, double scale, int spacing);

}  // namespace fluidtex
