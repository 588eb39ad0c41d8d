/// @file image.h
/// @brief Float images in memory and the texel kit every stage shares: the
/// uv ↔ pixel convention, texel indices, texel rectangles and tile grids,
/// bilinear lookup, Rec. 709 luminance. Pixels are linear float,
/// interleaved, row 0 at the top. Files are io/image_io.h's.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

#include "fluidtex/geometry/mesh.h"
#include "fluidtex/util/check.h"

namespace fluidtex {

/// The uv ↔ pixel convention of every atlas and exemplar, stated once: uv in
/// [0,1]² with v up (OBJ and DCCs); pixel rows top-down; pixel (x, y) covers
/// [x, x+1) × [y, y+1), its centre at (x + ½, y + ½).
inline double u_to_px(double u, int width) { return u * width; }
inline double v_to_py(double v, int height) { return (1.0 - v) * height; }
inline double px_to_u(double x, int width) { return x / width; }
inline double py_to_v(double y, int height) { return 1.0 - y / height; }

/// Index of texel (x, y) in a row-major grid `width` texels wide.
inline std::size_t texel_index(int x, int y, int width) { return static_cast<std::size_t>(y) * width + x; }

/// A half-open rectangle of texels [x0, x1) × [y0, y1).
struct Rect2i {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;

  bool empty() const { return x1 <= x0 || y1 <= y0; }
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
  /// Grown by `pad` texels on every side.
  Rect2i grown(int pad) const { return {x0 - pad, y0 - pad, x1 + pad, y1 + pad}; }
  /// The intersection (empty when they do not overlap).
  Rect2i operator&(const Rect2i& o) const {
    return {std::max(x0, o.x0), std::max(y0, o.y0), std::min(x1, o.x1), std::min(y1, o.y1)};
  }
  /// f(x, y) for every texel, row by row.
  template <class F>
  void for_each(F&& f) const {
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) f(x, y);
    }
  }
};

/// The texels whose centres (x + ½, y + ½) may lie in the box [lo, hi] of
/// texel coordinates (conservative: a texel more where a centre is on the edge).
inline Rect2i texel_box(const Vec2& lo, const Vec2& hi) {
  return {static_cast<int>(std::floor(lo.x() - 0.5)), static_cast<int>(std::floor(lo.y() - 0.5)),
          static_cast<int>(std::ceil(hi.x() - 0.5)) + 1, static_cast<int>(std::ceil(hi.y() - 0.5)) + 1};
}

/// A width × height grid cut into square tiles of `tile` texels (the last
/// row and column clipped), numbered row by row.
struct TileGrid {
  int width, height, tile;

  int columns() const { return (width + tile - 1) / tile; }
  int rows() const { return (height + tile - 1) / tile; }
  std::size_t count() const { return static_cast<std::size_t>(columns()) * rows(); }
  Rect2i rect(std::size_t index) const {
    const int tx = static_cast<int>(index % columns()), ty = static_cast<int>(index / columns());
    return Rect2i{tx * tile, ty * tile, tx * tile + tile, ty * tile + tile} & Rect2i{0, 0, width, height};
  }
  /// The tile holding texel (x, y).
  std::size_t index_of(int x, int y) const { return static_cast<std::size_t>(y / tile) * columns() + x / tile; }
  /// f(index) for every tile `box` (clipped to the grid) touches, row by row.
  template <class F>
  void for_each_tile(const Rect2i& box, F&& f) const {
    const Rect2i b = box & Rect2i{0, 0, width, height};
    if (b.empty()) return;
    for (int ty = b.y0 / tile; ty <= (b.y1 - 1) / tile; ++ty) {
      for (int tx = b.x0 / tile; tx <= (b.x1 - 1) / tile; ++tx) f(static_cast<std::size_t>(ty) * columns() + tx);
    }
  }
};

struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> pixels;  ///< width*height*channels, interleaved, linear

  /// A width × height image of `channels` zeros.
  static Image blank(int width, int height, int channels) {
    return {width, height, channels, std::vector<float>(texel_index(0, height, width) * channels, 0.0f)};
  }
  /// The channels of pixel i = texel_index(x, y, width).
  float* pixel(std::size_t i) {
    FLUIDTEX_DCHECK_LT(i * channels, pixels.size());
    return &pixels[i * channels];
  }
  const float* pixel(std::size_t i) const {
    FLUIDTEX_DCHECK_LT(i * channels, pixels.size());
    return &pixels[i * channels];
  }
  float& at(int x, int y, int c) { return pixel(texel_index(x, y, width))[c]; }
  float at(int x, int y, int c) const { return pixel(texel_index(x, y, width))[c]; }
  bool empty() const { return pixels.empty(); }
};

/// Bilinear lookup of `image` at texel coordinates (x right, y down, texel
/// centres at +0.5), clamped at the border; writes the first `channels`
/// values (0: all image.channels).
void sample_bilinear(const Image& image, double x, double y, float* out, int channels = 0);

/// The uv of the lower-left corner of UDIM tile `udim` (1001 + column +
/// 10·row covers uv [column, column + 1) × [row, row + 1)).
inline Vec2 udim_origin(int udim) {
  return {static_cast<double>((udim - 1001) % 10), static_cast<double>((udim - 1001) / 10)};
}

/// An atlas read back: one image, or UDIM tiles.
struct TiledAtlas {
  std::vector<int> udims;    ///< ascending; {1001} for one image
  std::vector<Image> tiles;  ///< the image of each
  bool udim = false;         ///< read as UDIM tiles (else one image holds every uv, clamped to [0,1]²)

  /// One image as an atlas.
  static TiledAtlas one(Image image) { return {.udims = {1001}, .tiles = {std::move(image)}, .udim = false}; }

  const Image& first() const { return tiles.front(); }
  /// The tile holding `uv` (nullptr where no tile is), and `uv` in it ([0,1]²).
  const Image* tile_at(Vec2& uv) const;
  /// Bilinear lookup at `uv` (v up) in its tile, clamped into the tile;
  /// zeros where no tile is. Writes the first `channels` values (0: all).
  void sample(Vec2 uv, float* out, int channels = 0) const;
};

/// Rec. 709 luminance of linear RGB (the primaries atlases and exemplars
/// are read in): the height atlas, a displacement exemplar's grey and eval's
/// spectra all take it.
template <class T>
constexpr T rec709_luminance(T r, T g, T b) {
  return T(0.2126) * r + T(0.7152) * g + T(0.0722) * b;
}

/// Luminance of texel `i` of `image`: Rec. 709 of its first three channels,
/// or its first channel when it has fewer (grey, grey + alpha).
template <class T>
T luminance_at(const Image& image, std::size_t i) {
  const float* p = image.pixel(i);
  return image.channels >= 3 ? rec709_luminance<T>(p[0], p[1], p[2]) : p[0];
}

}  // namespace fluidtex
