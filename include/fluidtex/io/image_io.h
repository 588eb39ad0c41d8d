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

#include <string>
#include <vector>

namespace fluidtex {

/// The uv ↔ pixel convention of every atlas and exemplar, stated once: uv in
/// [0,1]² with v up (OBJ and DCCs); pixel rows top-down; pixel (x, y) covers
/// [x, x+1) × [y, y+1), its centre at (x + ½, y + ½).
inline double u_to_px(double u, int width) { return u * width; }
inline double v_to_py(double v, int height) { return (1.0 - v) * height; }
inline double px_to_u(double x, int width) { return x / width; }
inline double py_to_v(double y, int height) { return 1.0 - y / height; }

struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> pixels;  ///< width*height*channels, interleaved, linear

  float& at(int x, int y, int c) { return pixels[(static_cast<size_t>(y) * width + x) * channels + c]; }
  float at(int x, int y, int c) const { return pixels[(static_cast<size_t>(y) * width + x) * channels + c]; }
  bool empty() const { return pixels.empty(); }
};

/// Bilinear lookup of `image` at texel coordinates (x right, y down, texel
/// centres at +0.5), clamped at the border; writes the first `channels`
/// values (0: all image.channels).
void sample_bilinear(const Image& image, double x, double y, float* out, int channels = 0);

/// Reads subimage 0 of an image; throws InputError(path, "cannot read image:
/// <reason>") (one line) when the file is missing, unreadable, truncated or
/// not an image.
Image read_image(const std::string& path);

enum class PixelDepth { Default, Half, Float, UInt8, UInt16 };

struct ImageWriteOptions {
  /// Default: half for EXR, uint8 for PNG, uint16 for TIFF. A depth the format
  /// cannot hold (float PNG, integer EXR, half TIFF) is an InputError.
  PixelDepth depth = PixelDepth::Default;
  /// Channel names written to the file (EXR keeps them); empty: Y (1), Y,A (2),
  /// R,G,B (3), R,G,B,A (4+, then channelN).
  std::vector<std::string> channel_names;
};

/// Writes `image` to `path` atomically (temporary sibling + rename). Throws
/// InputError for an unsupported extension or depth (before anything is
/// created), InternalError when the buffer does not match its size or writing
/// fails.
void write_image(const std::string& path, const Image& image, const ImageWriteOptions& options = {});

}  // namespace fluidtex
