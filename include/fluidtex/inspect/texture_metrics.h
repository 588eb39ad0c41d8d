/// @file texture_metrics.h
/// @brief What an atlas looks like against its exemplar, measured on the
/// texels its charts cover: contrast (the loss Eq. 7's blending is there to
/// prevent) and the radially averaged power spectrum (feature size and
/// sharpness), at the atlas's texel density.
#pragma once

#include <utility>
#include <vector>

#include "fluidtex/geometry/image.h"
#include "fluidtex/geometry/uv_mesh.h"
#include "fluidtex/texture/exemplar.h"

namespace fluidtex {

/// Texels of a `size`² atlas covered by the uv triangles of `mesh` (texel
/// centre inside a uv triangle): the chart texels. Of UDIM tiles, those of
/// the tile whose lower-left uv is `origin` (udim_origin).
std::vector<char> chart_mask(const UVMesh& mesh, int size, const Vec2& origin = Vec2::Zero());

/// n×n windows (top-left corners) of a `size`² atlas lying wholly inside
/// the charts of `mask`, at most `limit`, spread over the candidates in
/// scan order (deterministic).
std::vector<std::pair<int, int>> chart_windows(const std::vector<char>& mask, int size, int n, int limit);

/// Atlas texels per scene unit of `mesh` in a `size`² atlas (the square root
/// of the uv area in texels over the surface area).
double texel_density(const UVMesh& mesh, int size);

/// σ of each channel of `image` over the texels where `mask` is set,
/// divided by the σ of the exemplar resampled at `scale` exemplar texels
/// per image texel (resampled_stddev: the exemplar as it lands on the
/// surface, so that the bilinear blur of a magnified exemplar is not a loss
/// of contrast). 1 = contrast kept; linear blending of k uncorrelated
/// patches gives about 1/sqrt(k).
std::vector<double> contrast_ratio(const Image& image, const std::vector<char>& mask, const Exemplar& exemplar,
                                   double scale);

/// Radially averaged log power spectrum (luminance, Hann window, DC left
/// out) of the n×n crop of `image` at (x0, y0); n a power of two. Bin k
/// averages the frequencies with k <= |f| < k+1, k = 1 .. n/2 − 1.
std::vector<double> radial_log_spectrum(const Image& image, int x0, int y0, int n);

/// RMS difference of two radial log spectra (natural log units).
double spectrum_distance(const std::vector<double>& a, const std::vector<double>& b);

/// The exemplar resampled (bilinear, tiled) at `scale` exemplar texels per
/// output texel, an n×n crop starting at exemplar texel (x0, y0).
Image exemplar_crop(const Exemplar& exemplar, double x0, double y0, double scale, int n);

/// `crops` square crops of the exemplar resampled at `scale` exemplar
/// texels per output texel (exemplar_crop), each at least one tile wide
/// (the tile's width at that scale, clamped to 64 .. 512 texels), at fixed
/// offsets spread over the tile: the texels an atlas shows where the
/// exemplar lands at that scale, bilinear blur included.
std::vector<Image> exemplar_tiles(const Exemplar& exemplar, double scale, int crops = 4);

/// σ of each colour channel (Exemplar::channels) of the exemplar resampled
/// at `scale`, over exemplar_tiles (whose offsets fall between texels: the
/// σ of bilinear lookups at any phase, below the exemplar's own even at
/// scale 1 for a texture with detail at the texel).
std::vector<double> resampled_stddev(const Exemplar& exemplar, double scale);

/// The mean radial log spectrum (n×n) of `crops` crops of the exemplar at
/// `scale` exemplar texels per output texel, spread over the tile by fixed
/// offsets: the spectrum an atlas shows where the exemplar lands at that
/// scale.
std::vector<double> exemplar_spectrum(const Exemplar& exemplar, double scale, int n, int crops = 32);

/// What one exemplar tile spans on the surface as an atlas shows it, in
/// scene units: the span T whose exemplar spectrum (exemplar_spectrum at
/// W / (T·ρ) exemplar texels per atlas texel; W the exemplar's width, ρ the
/// texel density of `mesh`) is closest in shape (each spectrum less its
/// mean) to the mean spectrum of the atlas windows inside the charts,
/// searched from `expected` / 4 to 4·`expected` and refined between grid
/// steps. NaN when no 16×16 window lies inside the charts. It measures the
/// texture's size from the outputs alone, whatever the job was told.
double measured_exemplar_span(const Image& atlas, const UVMesh& mesh, const Exemplar& exemplar, double expected);

}  // namespace fluidtex
