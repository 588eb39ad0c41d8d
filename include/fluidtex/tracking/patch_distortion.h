/// @file patch_distortion.h
/// @brief How distorted an advected patch is (Gagnon et al. 2019, Sec. 5.3,
/// with Sorkine et al. 2002's measure, geometry/distortion.h), and whether
/// that retires it.
#pragma once

#include "fluidtex/geometry/surface.h"
#include "fluidtex/tracking/fading.h"
#include "fluidtex/tracking/options.h"
#include "fluidtex/tracking/patch.h"

namespace fluidtex {

/// Distortion of a patch on its current surface: per-triangle D_T (Sorkine),
/// per-vertex Q_V (mean Q_T of the incident triangles, weighted by their rest
/// area, a departure that keeps sliver triangles of reconstructed surfaces
/// from deciding alone) stored in
/// `patch.quality`, `patch.max_distortion` set. Returns the rule that found
/// the patch too distorted, None when it is fine.
///
/// DistortionTest::Patch (the default): the disk shows too little
/// undistorted texture, Σ seen_weight·Q_T < Q_vmin · patch.disk_weight over
/// its triangles, where flipped triangles, triangles across two surface
/// components and triangles lost in advection count Q_T = 0; the largest of
/// those losses names the cause (VerticesLost, Split, Flipped or Quality).
///
/// DistortionTest::Vertex: a triangle whose corners lie on different
/// connected components of the surface (Split), a triangle flipped against
/// the surface normal (Flipped), or a vertex with Q_V < Q_vmin (Quality), in
/// that order. Departure from the
/// paper, which tests every vertex: only vertices and triangles inside the
/// disk (|uv| < d, where K_S > 0) are tested, since the selection margin out
/// to (1 + β)d carries no weight and its distortion cannot be seen; on real
/// simulations this margin collapses on ridges and creases and would retire
/// most patches within a few frames.
RetireCause update_distortion(Patch& patch, const SurfaceIndex& surface, const TrackingOptions& options);

}  // namespace fluidtex
