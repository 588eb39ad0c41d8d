/// @file appearance_metrics.h
/// @brief How much an atlas still looks like its exemplar, measured on the
/// texels its charts cover against the exemplar resampled where it lands on
/// the surface (`scale` exemplar texels per atlas texel, as
/// texture_metrics.h's exemplar_crop resamples it, so that the bilinear blur
/// of a magnified exemplar is not counted against the atlas):
///
/// - orientation: the structure tensor of luminance gradients summed over
///   windows of one exemplar tile (Bigün and Granlund 1987; Jähne, *Spatio-
///   Temporal Image Processing*, 1993): how directional the texture is
///   (coherence (λ1 − λ2)/(λ1 + λ2)) and which way (the histogram of the
///   windows' dominant directions), against the exemplar's; the direction
///   is compared both as drawn and up to a rotation, since the liquid may
///   legitimately turn a patch;
/// - the nearest-window energy of texture optimisation (Kwatra, Essa,
///   Bobick and Kwatra, *Texture Optimization for Example-based Synthesis*,
///   SIGGRAPH 2005, Eq. 1): the squared distance of atlas windows to the
///   nearest exemplar window at any of 8 rotations, over the same energy of
///   the exemplar's own windows at an arbitrary turn and phase: structure
///   the exemplar does not have (overlaid copies, seams, smears) has no
///   close exemplar window;
/// - the colour distribution: the 1-D Wasserstein distance (earth mover's
///   distance; Rubner, Tomasi and Guibas 2000) between the chart texels'
///   values and the resampled exemplar's, per channel, in units of the
///   exemplar's σ;
/// - whether the patch layout shows: the normalized autocorrelation of
///   luminance at a lag of the patch spacing, against the exemplar's own at
///   the same lag. Where neighbouring patches show the same exemplar region,
///   the same feature repeats at the patch spacing and the atlas correlates
///   there more than the exemplar does. Read in fixed directions over the
///   charts (layout_figures) it sees a repeat on a lattice; the repeats of
///   an irregular (Poisson disk) layout lie each at its own displacement,
///   which only the correlation around each pair of neighbouring centres
///   at their displacement sees (neighbour_figures).
///
/// Directions and windows are read on the surface, not in the atlas: the
/// UV mesh maps each atlas window to a plane fixed in the world
/// (DirectionFrame), so that the turns and mirrors of the atlas's charts do
/// not count, only those of the texture on the surface.
///
/// Every figure is deterministic: windows and exemplar positions are fixed
/// (chart_windows, fixed offsets, counter-based random numbers of a fixed
/// seed), and the parallel loops write only their own slots, reduced in a
/// fixed order: the same inputs give the same numbers whatever the thread
/// count.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "fluidtex/geometry/image.h"
#include "fluidtex/geometry/surface.h"
#include "fluidtex/geometry/uv_mesh.h"
#include "fluidtex/texture/exemplar.h"

namespace fluidtex {

/// The plane in which directions on the surface are measured: the world
/// directions the exemplar's u and v run along in a planar projection (the
/// flow map's rest uv, flowmap.h's rest_uv: x and y for the axis z). A
/// surface direction t reads as (t·u, t·v), so that the exemplar projected
/// onto the surface, however the atlas lays out, turns or mirrors its
/// charts, reads as the exemplar itself.
struct DirectionFrame {
  Vec3 u = Vec3::UnitX();
  Vec3 v = Vec3::UnitY();
};

/// The orientation of a texture over square windows (structure tensor
/// J = Σ ∇L ∇Lᵀ of the luminance L, its gradients taken with derivative-of-
/// Gaussian filters of σ = 1 texel, summed over each window).
struct TextureOrientation {
  /// Mean over the windows of (λ1 − λ2)/(λ1 + λ2) of each window's J: 0 for
  /// an isotropic texture, 1 for straight stripes. NaN without windows.
  double coherence = 0.0;
  /// Per window: the direction along its features (perpendicular to the
  /// dominant gradient), in radians in [0, π), counter-clockwise from the
  /// frame's u (the image's +x, as the image is seen, rows down, without a
  /// frame).
  std::vector<double> angles;
  /// Per window: coherence · energy (the mean |∇L|² over its texels), the
  /// weight of its direction; 0 where the direction cannot be read in the
  /// frame.
  std::vector<double> weights;
};

/// Per n×n window (top-left `corners`) of a `size`² atlas, the linear map
/// from atlas texel displacements (x right, y up) to `frame` coordinates of
/// the surface `mesh` maps there: the mean, weighted by uv area, of the
/// maps of the uv triangles whose centroid lies in the window, or, where
/// none does (triangles larger than the window), the map of the triangle
/// holding its centre; zero where none does.
std::vector<Eigen::Matrix2d> window_frames(const UVMesh& mesh, int size,
                                           const std::vector<std::pair<int, int>>& corners, int n,
                                           const DirectionFrame& frame);

/// The n×n view of `atlas` centred on texel coordinates `centre` (x right,
/// y down) as the surface shows it in the frame: texel (i, j) is the
/// bilinear lookup (every channel) at its offset from the centre turned
/// back by the rotation of `map` (its orthogonal polar factor, a mirror
/// included; `map` as window_frames gives it; none for a zero map). Where
/// the texture is unturned on the surface, it reads as exemplar_crop does.
Image surface_view(const Image& atlas, const Vec2& centre, const Eigen::Matrix2d& map, int n);

/// The orientation of `image` over the n×n windows whose top-left corners
/// are `corners` (each inside the image). The gradients are those of the
/// whole image; each window sums J over its texels at least 2 texels from
/// its edge, so that texels outside a window (outside the charts) do not
/// count. With `frames` (window_frames; one per window), each window's J
/// is read in the frame (J' = A⁻ᵀ J A⁻¹): its coherence and direction are
/// those on the surface; a window whose map squashes one direction more
/// than twice against the other (the surface turned more than about 60°
/// from the frame's plane, where a planar projection smears) keeps its
/// coherence in the atlas and has no direction weight.
TextureOrientation texture_orientation(const Image& image, const std::vector<std::pair<int, int>>& corners, int n,
                                       const std::vector<Eigen::Matrix2d>& frames = {});

/// The orientation of the exemplar resampled at `scale` exemplar texels per
/// output texel (tiled, not rotated), over `crops` n×n windows at fixed
/// offsets spread over the tile: what an atlas shows where the exemplar
/// lands unrotated at that scale.
TextureOrientation exemplar_texture_orientation(const Exemplar& exemplar, double scale, int n, int crops = 16);

/// The windows' directions as a histogram of `bins` bins over [0, π),
/// weighted by TextureOrientation::weights and summing to 1 (all zeros when no
/// window has weight), of the angles less `reference` (so that bin 0 is
/// centred on `reference`).
std::vector<double> direction_histogram(const TextureOrientation& o, int bins = 12, double reference = 0.0);

/// The dominant direction of `o`: half the angle of Σ weight·(cos 2θ,
/// sin 2θ), in [0, π); NaN when no window has weight.
double dominant_direction(const TextureOrientation& o);

/// Half the L1 distance of two histograms that sum to 1: in [0, 1], 0 when
/// equal, 1 when disjoint.
double histogram_half_l1(const std::vector<double>& a, const std::vector<double>& b);

/// How an atlas's orientation compares with the exemplar's at the scale it
/// lands at (orientation_figures).
struct OrientationFigures {
  double coherence = 0.0;           ///< the atlas's (TextureOrientation::coherence)
  double exemplar_coherence = 0.0;  ///< the resampled exemplar's
  double coherence_ratio = 0.0;     ///< coherence / exemplar_coherence (1 = as directional as the exemplar)
  double histogram_distance = 0.0;  ///< histogram_half_l1 of the direction histograms as drawn
  /// The same with each histogram centred on its own dominant direction: a
  /// turned copy scores 0, a mixture of directions (patches turned
  /// differently) does not.
  double aligned_histogram_distance = 0.0;
  double angle_deg = 0.0;  ///< between the dominant directions, in [0, 90] degrees
  int window = 0;          ///< the windows' side, atlas texels
};

/// The orientation of the chart texels of `atlas` (`mask`, as chart_mask),
/// read on the surface through `mesh` in `frame`, against the exemplar's at
/// `scale` exemplar texels per atlas texel, over
/// windows the size of one exemplar tile at that scale (clamped to 16 .. 128
/// texels; halved down to 16 where none lies inside the charts), at most 64
/// windows (chart_windows), and 16 exemplar crops. Every figure NaN when no
/// 16×16 window lies inside the charts.
OrientationFigures orientation_figures(const Image& atlas, const UVMesh& mesh, const std::vector<char>& mask,
                                       const Exemplar& exemplar, double scale, const DirectionFrame& frame = {});

/// Settings of window_energy_ratio.
struct WindowEnergyOptions {
  int window = 8;                      ///< side of a window, atlas texels
  int samples = 400;                   ///< atlas windows (and exemplar reference windows) measured, at most
  int rotations = 8;                   ///< exemplar rotations searched, 360°/rotations apart
  int max_exemplar_windows = 1 << 17;  ///< exemplar windows searched, all rotations together (coarser stride beyond)
};

/// Kwatra et al. 2005's energy, normalised. The atlas's windows: up to
/// options.samples window × window windows of the chart texels of `atlas`
/// (luminance; centred in chart_windows of window·√2, deterministic), each
/// read (bilinear) along `frame`'s axes as `mesh` lays its chart on the
/// surface (window_frames' rotation, a mirror included: the window as the
/// surface shows it). Its energy: the mean squared distance of each to the
/// nearest window of the exemplar resampled at `scale` exemplar texels per
/// atlas texel and turned by any of options.rotations angles (windows on a
/// grid over one tile, one atlas texel apart, or coarser so that at most
/// options.max_exemplar_windows are searched). The reference: the same
/// energy of as many windows of the exemplar itself as an atlas shows it
/// and the same reading reads it back (turned by a random angle, on a
/// chart turned by another, at a random position; fixed pseudo-random
/// numbers, the same on every call). The ratio: 1 = as close to the
/// exemplar as the exemplar itself at an arbitrary turn and phase; an
/// unturned copy scores below 1 (0 on the grid's phase); turns between the
/// searched angles up to about 2; structure the exemplar does not have
/// (overlaid copies of a structured exemplar, seams, smears) more.
/// Contrast lost to blending is contrast_ratio's to see: a washed-out
/// window of a texture with flat areas is close to those. NaN when no
/// window lies inside the charts.
double window_energy_ratio(const Image& atlas, const UVMesh& mesh, const std::vector<char>& mask,
                           const Exemplar& exemplar, double scale, const DirectionFrame& frame = {},
                           const WindowEnergyOptions& options = {});

/// The 1-D Wasserstein distance W1 = ∫₀¹ |F⁻¹(t) − G⁻¹(t)| dt between the
/// empirical distributions of `a` and `b` (any sizes; exact). NaN when one
/// is empty.
double wasserstein_1d(std::vector<double> a, std::vector<double> b);

/// Per channel of the exemplar, wasserstein_1d between the chart texels of
/// `atlas` (`mask`; every k-th of more than 2^20) and the texels of the
/// exemplar resampled at `scale`
/// (exemplar_tiles), divided by the resampled exemplar's σ of that channel,
/// then averaged over the channels: 0 = the same colours, about 0.8 for a
/// constant image at the exemplar's mean of a Gaussian-like texture. NaN
/// when no texel is in the charts.
double value_histogram_distance(const Image& atlas, const std::vector<char>& mask, const Exemplar& exemplar,
                                double scale);

/// Per point of `points`, the index of the nearest other (on nanoflann's
/// k-d tree, PointIndex; of two as near, the lower index); −1 for a lone
/// point.
std::vector<int> nearest_others(const std::vector<Vec3>& points);

/// The mean over `points` of the distance to the nearest other point
/// (nearest_others): the spacing of a layout of disk centres, in the
/// points' units. NaN with fewer than two points.
double mean_nearest_distance(const std::vector<Vec3>& points);

/// Settings of the autocorrelation measures.
struct AutocorrelationOptions {
  /// Directions of the lag over [0, π), π/directions apart (δ and −δ pair the
  /// same texels: twice as many over the circle).
  int directions = 8;
  int windows = 64;  ///< atlas windows inside the charts, at most (chart_windows)
  int crops = 16;    ///< exemplar crops, at fixed offsets over the tile
  /// Texels taken as a pair's first over all windows, at most: a coarser
  /// grid of them beyond (the same grid on every call).
  int max_origins = 1 << 19;
};

/// A normalized autocorrelation at one lag: per direction, the mean over
/// the texel pairs (x, x + δ) of (L(x) − μ)(L(x + δ) − μ)/σ²; 1 for a texture
/// that repeats at δ, about 0 for one that does not correlate that far.
struct Autocorrelation {
  double mean = 0.0;                 ///< over the directions that have pairs; NaN when none has
  std::vector<double> by_direction;  ///< direction k at kπ/directions from the image's +x; NaN without pairs
};

/// The autocorrelation of the luminance of `image` at `lag` texels over its
/// n×n windows whose top-left corners are `corners` (each inside the image):
/// pairs whose both texels lie in one window (the second a bilinear lookup
/// at x + δ), μ and σ over the windows' texels. Read inside windows that lie
/// wholly inside the charts, the lag is one on the surface (a chart turns,
/// mirrors and scales the surface by about the texel density; the
/// directions cover the circle); pairs across a seam are not read.
/// Deterministic and the same for any thread count (a slot per window,
/// summed in order).
Autocorrelation luminance_autocorrelation(const Image& image, const std::vector<std::pair<int, int>>& corners, int n,
                                          double lag, const AutocorrelationOptions& options = {});

/// The same over options.crops n×n crops of the exemplar resampled at
/// `scale` exemplar texels per texel (exemplar_crop: tiled, unturned), at
/// fixed offsets spread over the tile: what an atlas shows at `lag` where
/// the exemplar lands at that scale without a patch layout.
Autocorrelation exemplar_autocorrelation(const Exemplar& exemplar, double scale, int n, double lag,
                                         const AutocorrelationOptions& options = {});

/// How much the patch layout shows in an atlas (layout_figures).
struct LayoutFigures {
  double lag = 0.0;       ///< atlas texels: the patch spacing at the texel density
  double atlas = 0.0;     ///< the chart texels' autocorrelation at `lag` (Autocorrelation::mean)
  double exemplar = 0.0;  ///< the resampled exemplar's
  double excess = 0.0;    ///< atlas − exemplar: > 0 where features repeat at the patch spacing
  int window = 0;         ///< the windows' side, atlas texels
};

/// luminance_autocorrelation of the chart texels of `atlas` (`mask`, as
/// chart_mask) at `lag` atlas texels over windows of about 2·lag (1.5·lag
/// or 1.25·lag where none lies inside the charts; at least 16 texels),
/// against exemplar_autocorrelation at `scale` exemplar texels per atlas
/// texel over crops of the same side. Every figure but the lag NaN when no
/// window lies inside the charts or the lag or scale is not positive.
LayoutFigures layout_figures(const Image& atlas, const std::vector<char>& mask, const Exemplar& exemplar, double scale,
                             double lag, const AutocorrelationOptions& options = {});

/// Two neighbouring patch centres as an atlas shows them (neighbour_pairs).
struct NeighbourPair {
  Vec2 from, to;                     ///< atlas texel coordinates (x right, y down) of the centres
  Eigen::Matrix2d from_map, to_map;  ///< the surface's map there (window_frames' around each)
  Vec2 displacement;                 ///< from → to on the surface in frame coordinates, atlas texels (x right, y up)
};

/// Each of `centres` (scene units, on the surface `mesh` carries; `surface`
/// indexes its triangles, as TexturedFrame's does) with the nearest other
/// (nearest_others), located in a `size`² atlas through the closest point
/// of `mesh`, with the maps of windows of `n` texels around each
/// (window_frames) and their displacement, the 3D chord projected on
/// `frame`'s plane at `density` atlas texels per scene unit.
std::vector<NeighbourPair> neighbour_pairs(const UVMesh& mesh, const SurfaceIndex& surface, int size,
                                           const std::vector<Vec3>& centres, double density, int n,
                                           const DirectionFrame& frame = {});

/// Whether neighbouring patches show the same texture where they lie
/// (neighbour_figures).
struct NeighbourFigures {
  double atlas = 0.0;     ///< mean over the pairs of the correlation of the views around their two centres
  double exemplar = 0.0;  ///< the same of the exemplar resampled, at the pairs' displacements
  double excess = 0.0;    ///< atlas − exemplar: > 0 where neighbours show the same part of the exemplar
  int pairs = 0;          ///< pairs read
  int window = 0;         ///< the views' side, atlas texels
};

/// The normalized autocorrelation of the atlas at each pair's displacement,
/// read around its centres on the surface: the n×n views of `atlas` around
/// the two centres as the surface shows them (surface_view), correlated
/// as Σ (A − μ)(B − μ) / (n² σ²), μ and σ over every view's luminance, and
/// averaged over the pairs; against the same of 4 pairs per pair of n×n
/// crops of the exemplar at `scale` exemplar texels per atlas texel
/// (exemplar_crop, unturned, at fixed positions over the tile) the pair's
/// displacement apart: the correlation of two places that far apart on the
/// exemplar unbroken. Views about half the spacing wide (as eval takes
/// them) hold the part of the surface each patch dominates. Patches that show the same part of the exemplar at their
/// spacing correlate up to 1 (the repeat this catches, whatever the
/// direction and distance of each neighbour); patches with independent
/// anchors as the exemplar does. A pair is read where both views' turned
/// squares lie inside the charts (`mask`) and both maps keep directions
/// readable. Every figure NaN without such a pair. Deterministic and the
/// same for any thread count.
NeighbourFigures neighbour_figures(const Image& atlas, const std::vector<char>& mask, const Exemplar& exemplar,
                                   double scale, const std::vector<NeighbourPair>& pairs, int n);

}  // namespace fluidtex
