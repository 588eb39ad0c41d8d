/// @file maps.h
/// @brief Height and normal atlases made from the colour atlas, for
/// displacement and shading in a renderer (the paper's Fig. 13 shades with
/// the synthesised texture as a normal map).
///
/// The height is the colour atlas's Rec. 709 luminance: blending (Eq. 7 or
/// linear) is linear in the exemplar, so this is the height a grey copy of
/// the exemplar would synthesise (up to the [0,1] clamp per channel). The
/// normal map is tangent space in the atlas's own uv frame (+x along +u,
/// +y along +v, +z out of the surface), which is the frame a renderer
/// builds from the mesh's uvs.
#pragma once

#include "fluidtex/geometry/image.h"
#include "fluidtex/texture/atlas.h"
#include "fluidtex/texture/synthesis.h"

namespace fluidtex {

/// One channel: Rec. 709 luminance of a colour atlas (a one-channel atlas
/// is returned as it is).
Image height_map(const Image& color);

/// The tangent-space normal of the surface displaced by `bump_height` ×
/// height (scene units: white stands `bump_height` above black), encoded
/// as 0.5·n + 0.5 in three channels. Slopes are central differences between
/// texels of the same chart (one-sided at a chart's border), converted to
/// scene units by the atlas's texel density; texels outside the charts are
/// dilated from the charts as the colour atlas's are.
Image normal_map(const Image& height, const TexelMap& map, const Atlas& atlas, double bump_height);

}  // namespace fluidtex
