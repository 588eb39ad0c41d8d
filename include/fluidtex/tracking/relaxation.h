/// @file relaxation.h
/// @brief Plastic patches (departure from the paper): a patch stretched
/// beyond a yield lets its texture coordinates give way, over a few frames,
/// so that the stretch the flow puts into it stays bounded instead of
/// accumulating until the patch must fade out and be replaced.
///
/// The paper retires a patch once its distortion exceeds what Q_vmin allows
/// and cross-fades a new one in its place. On a liquid that stretches and
/// compresses back and forth (sloshing) or keeps stretching (a spreading
/// sheet) every patch gets there after a while, and every retirement is a
/// cross-fade: a change of the texture in place, which reads as flicker.
/// A plastic patch behaves as an elastic one up to the yield (its uv do not
/// move; the texture stretches with the liquid exactly as in the paper);
/// beyond it, each triangle's uv target is its uv triangle with the stretch
/// beyond the yield taken out (the singular values of its map to the surface
/// clamped to [1/yield, yield]), and each frame the uv move 1/relax-frames of
/// the way to the least-squares uv of those targets (one local/global step
/// in the manner of as-rigid-as-possible flattening), the disk centre kept at
/// uv 0. The texture then slides a little where the liquid stretches hard
/// rather than fading out there.
#pragma once

#include "fluidtex/tracking/options.h"
#include "fluidtex/tracking/patch.h"

namespace fluidtex {

/// Moves `patch.uvs` by `rate` ∈ (0, 1] of the way to the uv in which no
/// triangle of the patch is stretched or squeezed beyond `yield` (a Sorkine
/// stretch ≥ 1; 1 relaxes towards the isometric shape), keeping the point at
/// uv 0 where it is on the patch, and makes each triangle's rest shape its uv
/// triangle. patch.disk_weight is rescaled by how the disk's seen weight
/// changed, so triangles lost earlier still count as lost. Returns true when
/// the uv moved; false, leaving the patch as it was, when no triangle is
/// beyond the yield or no step short of folding a uv triangle exists.
bool relax_patch(Patch& patch, double rate, double yield, const TrackingOptions& options);

}  // namespace fluidtex
