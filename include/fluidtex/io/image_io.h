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

#include "fluidtex/geometry/image.h"
#include "fluidtex/util/enum_names.h"

namespace fluidtex {

/// Largest images read_image accepts (a header may claim any size; this
/// bounds the memory allocated before the pixels are seen): exemplars, and
/// the atlases of finished runs (--atlas-size is at most 32768).
inline constexpr long long kMaxImagePixels = 8192LL * 8192LL;
inline constexpr long long kMaxAtlasPixels = 32768LL * 32768LL;
inline constexpr int kMaxImageChannels = 16;

/// Reads subimage 0 of an image (at most `max_pixels` pixels and
/// kMaxImageChannels channels); throws InputError(path, "cannot read image:
/// <reason>") (one line) when the file is missing, unreadable, truncated or
/// not an image.
Image read_image(const std::string& path, long long max_pixels = kMaxImagePixels);

/// The values an image file is read as: decoded by read_image's rules, or
/// as the file stores them (float, no transfer function).
enum class ImageValues { Decoded, AsStored };

/// An image file read: its values, and the colour space the file names (its
/// `colorspace` attribute, else `oiio:ColorSpace`, which OpenImageIO sets to
/// "Linear" for every EXR; empty when none).
struct ImageFile {
  Image image;
  std::string color_space;
  int alpha = -1;  ///< the alpha channel, or -1
  /// Whether read_image's own rules decode this file (no colour space named,
  /// or one of sRGB, linear or gamma): a file naming another space (ACEScg,
  /// say) is read by them as linear Rec. 709.
  bool rules_apply = true;
};

/// read_image with what the file says of its colour, its values `values`.
ImageFile read_image_file(const std::string& path, ImageValues values, long long max_pixels = kMaxImagePixels);

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
  /// Colour already in this (OpenColorIO) space, written as it is and named
  /// in `oiio:ColorSpace` and a `colorspace` attribute (integer formats
  /// quantise it without the sRGB encoding; no chromaticities). Empty: linear Rec. 709, written as linear
  /// (float) or sRGB-encoded (integer).
  std::string color_space;
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
