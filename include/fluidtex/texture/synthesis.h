/// @file synthesis.h
/// @brief Texel synthesis into the frame's atlas (Gagnon et al. 2019, Sec. 6.4,
/// Eq. 7, after Yu et al. 2011): for every texel covered by a chart, the
/// patches overlapping its surface point, each patch's uv there and its
/// weight w (vertex weights interpolated), blended as blend.h says (Eq. 7,
/// linear, or histogram preserving).
///
/// Two ways to find, per texel, the covering patches:
///  - `Raster` (default): every patch vertex already has its projection on
///    the surface (triangle + barycentrics), hence an atlas position; a patch
///    triangle whose corners lie in one chart is rasterised straight into the
///    atlas. Triangles spanning charts (or next to a chart border) take the
///    projected fallback: the texels of the surface triangles under them are
///    projected onto them one by one, as in `Exact`.
///  - `Exact`: the paper's method (Sec. 7.1), each texel's 3D point projected
///    through every patch triangle near it; the reference for tests.
/// Both run in parallel over atlas tiles and accumulate each texel's
/// contributions in patch order, so the result does not depend on threads.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "fluidtex/texture/atlas.h"
#include "fluidtex/texture/blend.h"
#include "fluidtex/texture/exemplar.h"
#include "fluidtex/tracking/patch.h"
#include "fluidtex/util/enum_names.h"

namespace fluidtex {

enum class SynthesisScheme { Raster, Exact };

inline constexpr EnumName<SynthesisScheme> kSynthesisSchemeNames[] = {{SynthesisScheme::Raster, "raster"},
                                                                      {SynthesisScheme::Exact, "exact"}};
constexpr const auto& enum_names(SynthesisScheme) { return kSynthesisSchemeNames; }
inline const char* to_string(SynthesisScheme m) { return enum_name(m); }

struct SynthesisOptions {
  Blend blend = Blend::ContrastPreserving;
  SynthesisScheme scheme = SynthesisScheme::Raster;
  /// Scene units covered by one exemplar tile at uv scale s = 1; the lookup
  /// is anchor + s·uv / tile_size. Must be > 0 (the job sets (2 + β)·d).
  double tile_size = 1.0;
  double uv_scale = 1.0;  ///< s (Table 3)
  /// d, the disk radius: the support of each patch's core weight K_S·K_t
  /// (Eq. 4, 2; core_weight). A texel blends its patches' core weights; the
  /// coverage tail of the weights (update_weights) enters only as λ·tail,
  /// λ = clamp(1 − Σcore / (kCoverageTail·s), 0, 1), so it fills the slivers
  /// no disk reaches and fades out continuously where one does. Must be > 0
  /// (the job sets --radius).
  double radius = 0.0;
  /// t: a texel blends each patch's core weight lowered by t times the
  /// texel's largest core weight, max(0, core − t·max core), so patches far
  /// weaker than the texel's strongest drop out of the blend and the rest
  /// enter and leave it continuously. 0 blends every overlapping patch (the
  /// paper). In [0, 1).
  double weight_cutoff = 0.0;
  /// p: the (cut) core weights a texel blends are sharpened to
  /// w_max·(w/w_max)^p (blend.h, sharpened), so that most texels show one
  /// patch with a narrow transition to the next. 1 leaves them (the paper).
  double sharpness = 1.0;
  double projection_tolerance =
      0;             ///< projection slack (scene units) of Exact and the projected fallback; the job sets mpt
  bool aov = false;  ///< also fill weight / count / patch layers
};

struct SynthesisResult {
  Image color;                          ///< atlas colour (exemplar channels), gutters dilated
  Image weight;                         ///< Σw per texel (with aov)
  Image count;                          ///< number of patches blended per texel (with aov)
  Image patch;                          ///< dominant patch id as a colour (with aov)
  std::size_t chart_texels = 0;         ///< texels inside charts
  std::size_t uncovered_texels = 0;     ///< of those, texels with Σw = 0
  std::size_t margin_texels = 0;        ///< of those, texels only a patch's margin reaches (shown as a last resort)
  std::size_t clamped_texels = 0;       ///< texels where a channel left [0,1]
  std::size_t dominant_texels = 0;      ///< texels where one patch carries at least kDominantWeight of Σw
  std::size_t binned_triangles = 0;     ///< patch triangles with a core weight, binned into tiles (Raster)
  std::size_t projected_triangles = 0;  ///< of those, the ones that took the projected fallback
  double uncovered_fraction() const {
    return chart_texels ? static_cast<double>(uncovered_texels) / static_cast<double>(chart_texels) : 0.0;
  }
  /// Zeroed images of an n × n atlas: colour with `channels`, and the AOV
  /// layers when `aov`.
  static SynthesisResult blank(int n, int channels, bool aov) {
    SynthesisResult r;
    r.color = Image::blank(n, n, channels);
    if (aov) r.weight = Image::blank(n, n, 1), r.count = Image::blank(n, n, 1), r.patch = Image::blank(n, n, 3);
    return r;
  }
};

/// The share of a texel's blended weight from which one patch "carries" it
/// (SynthesisResult::dominant_texels).
inline constexpr double kDominantWeight = 0.9;

/// Which surface face (and where in it) each atlas texel centre shows.
struct TexelMap {
  int size = 0;
  int tile = 0;                                ///< the atlas tile it maps (Chart::tile)
  std::vector<int> face;                       ///< per texel (row-major, y down), −1 outside every chart
  std::vector<std::uint32_t> face_start;       ///< texels of face f: texels[face_start[f] .. face_start[f+1])
  std::vector<std::uint32_t> texels;           ///< texel indices grouped by face, ascending within a face
  std::vector<std::array<Vec2, 3>> corner_px;  ///< per face, its corners in the atlas (Atlas::corner_px)

  /// Barycentric coordinates of chart texel `i`'s centre in its face
  /// (face[i] ≥ 0), clamped into the face. Computed when asked, not stored:
  /// a stored copy would be 24 bytes per atlas texel (100 MB at 2048²).
  Vec3 bary(std::size_t i) const;
};

/// Rasterises the charts of atlas tile `tile`: that tile's texel → surface map.
TexelMap build_texel_map(const SurfaceIndex& surface, const Atlas& atlas, int tile = 0);

/// Synthesises the atlas tile that `map` maps from `patches` (their weights
/// must be current).
SynthesisResult synthesize(const SurfaceIndex& surface, const Atlas& atlas, const TexelMap& map,
                           const std::vector<Patch>& patches, const Exemplar& exemplar,
                           const SynthesisOptions& options);

/// Fills every texel outside the charts (mask == 0) within `rings` texels of
/// a chart with the mean of its filled 8-neighbours, ring by ring, so that
/// bilinear and mip-mapped lookups near chart borders see no seam.
void dilate(Image& image, std::vector<char>& mask, int rings);

}  // namespace fluidtex
