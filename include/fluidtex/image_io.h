/// @file image_io.h
/// @brief Float images in and out through OpenImageIO. Pixels are linear
/// float, interleaved, row 0 at the top.
///
/// Input (exemplars): any format and bit depth OpenImageIO reads. 8- and
/// 16-bit integer files without colour-space metadata, and files tagged sRGB,
/// are treated as sRGB-encoded and converted to linear; float files (EXR, HDR,
/// float TIFF) are taken as linear.
/// Output (atlases): the format comes from the extension. `.exr`: half (default)
/// or float; `.png`: 8-bit (or 16-bit) sRGB-encoded; `.tif`/`.tiff`: 16-bit
/// sRGB-encoded or float when requested.
#pragma once

#include <string>
#include <vector>

namespace fluidtex {

struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> pixels;  ///< width*height*channels, interleaved, linear

  float& at(int x, int y, int c) { return pixels[(static_cast<size_t>(y) * width + x) * channels + c]; }
  float at(int x, int y, int c) const { return pixels[(static_cast<size_t>(y) * width + x) * channels + c]; }
  bool empty() const { return pixels.empty(); }
};

/// Reads an image; throws InputError("<path>", "...") when the file is missing,
/// unreadable or not an image.
Image read_image(const std::string& path);

enum class PixelDepth { Default, Half, Float, UInt8, UInt16 };

struct ImageWriteOptions {
  /// Default: half for EXR, uint8 for PNG, uint16 for TIFF.
  PixelDepth depth = PixelDepth::Default;
  /// Channel names written to the file (EXR keeps them); empty: R,G,B,A / Y.
  std::vector<std::string> channel_names;
};

/// Writes `image` to `path` atomically (temporary sibling + rename). Throws
/// InputError for an unsupported extension, InternalError when writing fails.
void write_image(const std::string& path, const Image& image,
                 const ImageWriteOptions& options = {});

}  // namespace fluidtex
