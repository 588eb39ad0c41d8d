/// @file image_io.h
/// @brief Float images in and out through OpenImageIO. Pixels are linear
/// float, interleaved, row 0 at the top.
///
/// Input (exemplars): any format and bit depth OpenImageIO reads. 8- and
/// 16-bit integer files without colour-space metadata, and files tagged sRGB,
/// are treated as sRGB-encoded and converted to linear; float files (EXR, HDR,
/// float TIFF) are taken as linear (unless tagged sRGB); a file tagged
/// "GammaCorrected" with oiio:Gamma is decoded with that power. The exact sRGB
/// EOTF is applied here (no OCIO), so results never depend on the environment.
/// Output (atlases): the format comes from the extension (case-insensitive).
/// `.exr`: half (default) or float, linear, zip compression; `.png`: 8-bit
/// (or 16-bit) sRGB-encoded; `.tif`/`.tiff`: 16-bit (or 8-bit) sRGB-encoded,
/// or float (linear) when requested, zip compression. Integer encoding picks
/// the nearest code value in sRGB space (values clamped to [0,1], NaN -> 0),
/// so decoding and re-encoding an integer image is lossless.
/// Alpha (channel named A/alpha) is never colour-converted nor
/// (un)premultiplied: stored values pass through as given.
/// Outputs are byte-identical for identical images: no timestamps are written
/// (DateTime suppressed), Software is the constant "fluidtex".
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

#include <vector>
#include "fluidtex/util/enum_names.h"

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

/// Largest images read_image accepts (a header may claim any size; this
/// bounds the memory allocated before the pixels are seen): exemplars, and
/// the atlases of finished runs (--atlas-size is at most 32768).
/// Rec. 709 luminance of linear RGB (the primaries atlases and exemplars
/// are read in): the height atlas, a displacement exemplar's grey and eval's
/// spectra all take it.
template <class T>
constexpr T rec709_luminance(T r, T g, T b) {
  return T(0.2126) * r + T(0.7152) * g + T(0.0722) * b;
}

inline constexpr long long kMaxImagePixels = 8192LL * 8192LL;
inline constexpr long long kMaxAtlasPixels = 32768LL * 32768LL;
inline constexpr int kMaxImageChannels = 16;

/// Reads subimage 0 of an image (at most `max_pixels` pixels and
/// kMaxImageChannels channels); throws InputError(path, "cannot read image:
/// <reason>") (one line) when the file is missing, unreadable, truncated or
/// not an image.
Image read_image(const std::string& path, long long max_pixels = kMaxImagePixels);

enum class PixelDepth { Default, Half, Float, UInt8, UInt16 };

/// OpenEXR's compressions (the lossy ones: pxr24 on floats, b44, b44a,
/// dwaa, dwab).
enum class ExrCompression { Zip, None, Rle, Zips, Piz, Pxr24, B44, B44a, Dwaa, Dwab };
inline constexpr EnumName<ExrCompression> kExrCompressionNames[] = {
    {ExrCompression::Zip, "zip"},   {ExrCompression::None, "none"}, {ExrCompression::Rle, "rle"},
    {ExrCompression::Zips, "zips"}, {ExrCompression::Piz, "piz"},   {ExrCompression::Pxr24, "pxr24"},
    {ExrCompression::B44, "b44"},   {ExrCompression::B44a, "b44a"}, {ExrCompression::Dwaa, "dwaa"},
    {ExrCompression::Dwab, "dwab"}};
constexpr const auto& enum_names(ExrCompression) { return kExrCompressionNames; }

/// How the pixels are laid out in the file: scanlines (what most tools
/// expect), 64x64 tiles, or 64x64 tiles with every MIP level down to 1x1
/// (box filter), the texture a production renderer pages in; tiled layouts
/// are EXR only and are written by OpenImageIO's make_texture.
enum class TextureLayout { Scanline, Tiled, Mipmap };
inline constexpr EnumName<TextureLayout> kTextureLayoutNames[] = {
    {TextureLayout::Scanline, "scanline"}, {TextureLayout::Tiled, "tiled"}, {TextureLayout::Mipmap, "mipmap"}};
constexpr const auto& enum_names(TextureLayout) { return kTextureLayoutNames; }

struct ImageWriteOptions {
  /// Default: half for EXR, uint8 for PNG, uint16 for TIFF. A depth the format
  /// cannot hold (float PNG, integer EXR, half TIFF) is an InputError.
  PixelDepth depth = PixelDepth::Default;
  /// Channel names written to the file (EXR keeps them); empty: Y (1), Y,A (2),
  /// R,G,B (3), R,G,B,A (4+, then channelN).
  std::vector<std::string> channel_names;
  /// EXR compression (other formats ignore it) and, for dwaa/dwab, its level
  /// (OpenEXR's default 45; higher is smaller and lossier).
  ExrCompression compression = ExrCompression::Zip;
  int dwa_level = 45;
  /// Extra string attributes written to the file (EXR and TIFF keep them
  /// under these names; PNG as text chunks).
  std::vector<std::pair<std::string, std::string>> metadata;
  /// Scanline, tiled or MIP-mapped (EXR only; other formats: InputError).
  TextureLayout layout = TextureLayout::Scanline;
  /// Data, not colour (heights, normals): `oiio:ColorSpace` is "Raw" and an
  /// EXR gets no chromaticities.
  bool data = false;
};

/// Writes `image` to `path` atomically (temporary sibling + rename). Throws
/// InputError for an unsupported extension or depth (before anything is
/// created), InternalError when the buffer does not match its size or writing
/// fails.
void write_image(const std::string& path, const Image& image, const ImageWriteOptions& options = {});

/// The threads OpenImageIO and OpenEXR may use for reading and writing
/// images, process-wide: `threads` (> 0) in all, as the job's --threads
/// promises (OpenEXR's compression pool otherwise starts a thread per core
/// beside the job's own); 0 leaves both at one per core.
void limit_image_io_threads(int threads);

}  // namespace fluidtex
