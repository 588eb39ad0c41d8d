// Float images in and out through OpenImageIO (see image_io.h).
//
// Colour handling is done here with the exact sRGB transfer functions rather
// than through OIIO's colour management (OCIO), so the result does not depend
// on an OCIO config found at run time:
//  * decoding (read): EOTF  c <= 0.04045 ? c/12.92 : ((c+0.055)/1.055)^2.4
//  * encoding (write): a code value k is chosen as the nearest code value in
//    sRGB space, implemented as a binary search over the precomputed linear
//    thresholds EOTF((k+0.5)/max). Pure table look-ups: deterministic, and
//    decode followed by encode returns the original code values exactly.
// Alpha is never colour-converted and never (un)premultiplied: values pass
// through as given ("oiio:UnassociatedAlpha" on both read and write).
#include "fluidtex/io/image_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <string_view>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/strings.h"

namespace fluidtex {

namespace fs = std::filesystem;

namespace {

double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

bool is_float_type(OIIO::TypeDesc t) {
  return t.basetype == OIIO::TypeDesc::HALF || t.basetype == OIIO::TypeDesc::FLOAT ||
         t.basetype == OIIO::TypeDesc::DOUBLE;
}

/// How the stored values of a file map to linear light.
enum class Transfer { Linear, SRGB, Gamma };

/// Integer data is sRGB unless tagged linear (or with an explicit gamma);
/// float data is linear unless explicitly tagged sRGB.
Transfer transfer_of(const OIIO::ImageSpec& spec, float* gamma) {
  const std::string cs = to_lower(spec.get_string_attribute("oiio:ColorSpace"));
  if (cs.rfind("gammacorrected", 0) == 0 || cs.rfind("gamma", 0) == 0) {
    *gamma = spec.get_float_attribute("oiio:Gamma", 0.0f);
    if (*gamma > 0.0f && std::isfinite(*gamma)) return Transfer::Gamma;
  }
  if (cs == "srgb" || cs == "srgb_texture" || cs == "srgb_rec709_scene") return Transfer::SRGB;
  if (cs.find("linear") != std::string::npos || cs == "scene_linear" || cs == "lin_srgb" || cs == "lin_rec709")
    return Transfer::Linear;
  return is_float_type(spec.format) ? Transfer::Linear : Transfer::SRGB;
}

/// Alpha channel index of `spec`, or -1 (by the spec's own field or by name).
int alpha_index(const OIIO::ImageSpec& spec) {
  if (spec.alpha_channel >= 0 && spec.alpha_channel < spec.nchannels) return spec.alpha_channel;
  for (int c = 0; c < spec.nchannels && c < static_cast<int>(spec.channelnames.size()); ++c) {
    const std::string n = to_lower(spec.channelnames[c]);
    if (n == "a" || n == "alpha") return c;
  }
  return -1;
}

/// Linear thresholds between successive code values 0..max_code of an sRGB
/// encoding: code = number of thresholds <= value.
std::vector<float> srgb_thresholds(int max_code) {
  std::vector<float> t(static_cast<size_t>(max_code));
  for (int k = 0; k < max_code; ++k) t[k] = static_cast<float>(srgb_to_linear((k + 0.5) / max_code));
  return t;
}

template <typename T>
T quantise(float v, bool srgb, const std::vector<float>& thresholds, int max_code) {
  if (!(v > 0.0f)) return 0;  // also NaN
  if (srgb) {
    return static_cast<T>(std::upper_bound(thresholds.begin(), thresholds.end(), v) - thresholds.begin());
  }
  if (v >= 1.0f) return static_cast<T>(max_code);
  return static_cast<T>(std::lround(static_cast<double>(v) * max_code));
}

/// Integer code values of `image`: colour channels sRGB-encoded when
/// `srgb` (else, as alpha always, quantised linearly).
template <typename T>
std::vector<T> encode_integer(const Image& image, int alpha, int max_code, bool srgb) {
  const std::vector<float> thresholds = srgb_thresholds(max_code);
  std::vector<T> out(image.pixels.size());
  const size_t row = static_cast<size_t>(image.width) * image.channels;
  tbb::parallel_for(0, image.height, [&](int y) {
    const size_t base = static_cast<size_t>(y) * row;
    for (size_t i = 0; i < row; ++i) {
      const int c = static_cast<int>(i % image.channels);
      out[base + i] = quantise<T>(image.pixels[base + i], srgb && c != alpha, thresholds, max_code);
    }
  });
  return out;
}

enum class Format { Exr, Png, Tiff };

Format format_of(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".exr") return Format::Exr;
  if (ext == ".png") return Format::Png;
  if (ext == ".tif" || ext == ".tiff") return Format::Tiff;
  throw InputError(path, "unsupported image extension '" + fs::path(path).extension().string() +
                             "' (use .exr, .png, .tif or .tiff)");
}

OIIO::TypeDesc pixel_type(const std::string& path, Format format, PixelDepth depth) {
  switch (format) {
    case Format::Exr:
      if (depth == PixelDepth::Default || depth == PixelDepth::Half) return OIIO::TypeDesc::HALF;
      if (depth == PixelDepth::Float) return OIIO::TypeDesc::FLOAT;
      throw InputError(path, "EXR atlases hold half or float pixels, not 8/16-bit integers");
    case Format::Png:
      if (depth == PixelDepth::Default || depth == PixelDepth::UInt8) return OIIO::TypeDesc::UINT8;
      if (depth == PixelDepth::UInt16) return OIIO::TypeDesc::UINT16;
      throw InputError(path, "PNG holds 8- or 16-bit integers only; use .exr or .tif for float");
    case Format::Tiff:
      if (depth == PixelDepth::Default || depth == PixelDepth::UInt16) return OIIO::TypeDesc::UINT16;
      if (depth == PixelDepth::UInt8) return OIIO::TypeDesc::UINT8;
      if (depth == PixelDepth::Float) return OIIO::TypeDesc::FLOAT;
      // OIIO's TIFF writer would silently widen half to float.
      throw InputError(path, "TIFF atlases hold 8/16-bit integers or float; use .exr for half");
  }
  return OIIO::TypeDesc::FLOAT;
}

std::vector<std::string> channel_names(const Image& image, const ImageWriteOptions& options, const std::string& path) {
  if (!options.channel_names.empty()) {
    if (static_cast<int>(options.channel_names.size()) != image.channels)
      throw InternalError(path + ": " + std::to_string(options.channel_names.size()) + " channel names given for " +
                          std::to_string(image.channels) + " channels");
    return options.channel_names;
  }
  switch (image.channels) {
    case 1: return {"Y"};
    case 2: return {"Y", "A"};
    case 3: return {"R", "G", "B"};
    default: {
      std::vector<std::string> names{"R", "G", "B", "A"};
      for (int c = 4; c < image.channels; ++c) names.push_back("channel" + std::to_string(c));
      return names;
    }
  }
}

}  // namespace

namespace {

/// libpng prints its errors on stderr itself (OpenImageIO's PNG reader does
/// not route them), which would make a second line next to fluidtex's. While
/// a PNG is read, file descriptor 2 goes to a temporary file; what was
/// printed is returned by text(). Process-wide, so captures are serialised.
class StderrCapture {
 public:
  StderrCapture() : lock_(mutex()) {
    std::fflush(stderr);
    file_ = std::tmpfile();
    saved_ = file_ ? ::dup(STDERR_FILENO) : -1;
    if (saved_ >= 0) ::dup2(::fileno(file_), STDERR_FILENO);
  }
  ~StderrCapture() { restore(); }
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;

  /// Restores stderr; the captured text, on one line.
  std::string text() {
    restore();
    return captured_;
  }

 private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  void restore() {
    if (saved_ < 0) return;
    std::fflush(stderr);
    ::dup2(saved_, STDERR_FILENO);
    ::close(saved_);
    saved_ = -1;
    std::rewind(file_);
    char buf[512];
    std::size_t n = 0;
    while ((n = std::fread(buf, 1, sizeof buf, file_)) > 0 && captured_.size() < 4096) captured_.append(buf, n);
    std::fclose(file_);
    file_ = nullptr;
    captured_ = one_line(captured_);
  }
  std::unique_lock<std::mutex> lock_;
  std::FILE* file_ = nullptr;
  int saved_ = -1;
  std::string captured_;
};

Image decode_image(const std::string& path, long long max_pixels, OIIO::ImageSpec& spec);
void linearise(Image& image, const OIIO::ImageSpec& spec);
Image read_spec_and_pixels(const std::string& path, long long max_pixels, OIIO::ImageSpec& spec);

}  // namespace

Image read_image(const std::string& path, long long max_pixels) {
  return read_image_file(path, ImageValues::Decoded, max_pixels).image;
}

ImageFile read_image_file(const std::string& path, ImageValues values, long long max_pixels) {
  OIIO::ImageSpec spec;
  ImageFile file;
  file.image = read_spec_and_pixels(path, max_pixels, spec);
  if (values == ImageValues::Decoded) linearise(file.image, spec);
  // OpenImageIO reads every EXR as "Linear": an EXR names its space in a
  // `colorspace` attribute (as write_image writes it).
  file.color_space = spec.get_string_attribute("colorspace");
  if (file.color_space.empty()) file.color_space = spec.get_string_attribute("oiio:ColorSpace");
  file.alpha = alpha_index(spec);
  float gamma = 1.0f;
  const Transfer transfer = transfer_of(spec, &gamma);
  const std::string tag = to_lower(file.color_space);
  file.rules_apply = tag.empty() || transfer != Transfer::Linear || tag.find("linear") != std::string::npos ||
                     tag == "lin_srgb" || tag == "lin_rec709" || tag == "raw";
  return file;
}

namespace {

/// The file's spec and its pixels as stored (float), through read_image's checks.
Image read_spec_and_pixels(const std::string& path, long long max_pixels, OIIO::ImageSpec& spec) {
  try {
    require_regular_file(path, "the file");
  } catch (const InputError& e) {
    throw InputError(path, "cannot read image: " + e.problem());
  }
  Image image;
  if (lower_extension(path) != ".png") {
    image = decode_image(path, max_pixels, spec);
  } else {
    // Only around the decoder: the capture holds a process-wide lock, which
    // must not be held across the parallel conversion below (a TBB thread
    // waiting there may run another read_image).
    StderrCapture capture;
    try {
      image = decode_image(path, max_pixels, spec);
    } catch (const InputError& e) {
      const std::string printed = capture.text();
      if (printed.empty() || e.problem().find(printed) != std::string::npos) throw;
      throw InputError(path, e.problem() + " (" + printed + ")");
    }
  }
  return image;
}

/// The pixels as stored (float), and the file's spec.
Image decode_image(const std::string& path, long long max_pixels, OIIO::ImageSpec& spec) {
  auto fail = [&](const std::string& reason) { return InputError(path, "cannot read image: " + reason); };

  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) {
    std::string reason = one_line(OIIO::geterror());
    if (reason.empty()) reason = "not an image in a format OpenImageIO reads";
    throw fail(reason);
  }
  spec = in->spec();
  if (spec.deep) throw fail("deep images are not supported");
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) throw fail("empty image");
  if (spec.depth > 1) throw fail("volume images are not supported");

  const double pixels = static_cast<double>(spec.width) * spec.height;
  if (pixels > static_cast<double>(max_pixels) || spec.nchannels > kMaxImageChannels) {
    throw fail(std::to_string(spec.width) + "x" + std::to_string(spec.height) + " pixels, " +
               std::to_string(spec.nchannels) + " channels: more than fluidtex reads (at most " +
               std::to_string(max_pixels) + " pixels and " + std::to_string(kMaxImageChannels) + " channels)");
  }
  Image image;
  image.width = spec.width;
  image.height = spec.height;
  image.channels = spec.nchannels;
  image.pixels.resize(static_cast<size_t>(image.width) * image.height * image.channels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data())) {
    std::string reason = one_line(in->geterror());
    if (reason.empty()) reason = "read failed (truncated or corrupt file?)";
    throw fail(reason);
  }
  in->close();
  (void)OIIO::geterror();  // clear any stale global message
  return image;
}

/// Integer and sRGB-tagged files to linear (see the header).
void linearise(Image& image, const OIIO::ImageSpec& spec) {
  float gamma = 1.0f;
  const Transfer transfer = transfer_of(spec, &gamma);
  if (transfer == Transfer::Linear) return;
  const int alpha = alpha_index(spec);
  const size_t row = static_cast<size_t>(image.width) * image.channels;
  tbb::parallel_for(0, image.height, [&](int y) {
    float* p = image.pixels.data() + static_cast<size_t>(y) * row;
    for (size_t i = 0; i < row; ++i) {
      if (static_cast<int>(i % image.channels) == alpha) continue;
      const double v = p[i];
      p[i] = static_cast<float>(transfer == Transfer::SRGB ? srgb_to_linear(v) : std::pow(std::max(v, 0.0), gamma));
    }
  });
}

}  // namespace

namespace {

/// A tiled (and MIP-mapped) EXR texture through OpenImageIO's make_texture:
/// 64x64 tiles, box-filtered levels, the file's attributes from `spec`
/// (its empty DateTime keeps make_texture from stamping the time, so the
/// bytes stay those of the pixels).
void write_texture(const std::string& path, const Image& image, const OIIO::ImageSpec& spec, OIIO::TypeDesc type,
                   TextureLayout layout) {
  OIIO::ImageSpec float_spec = spec;
  float_spec.set_format(OIIO::TypeDesc::FLOAT);
  OIIO::ImageBuf buffer(float_spec);
  buffer.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, image.pixels.data());
  OIIO::ImageSpec config;
  config.tile_width = config.tile_height = 64;
  config.format = type;
  config.attribute("maketx:filtername", "box");
  config.attribute("maketx:nomipmap", layout == TextureLayout::Tiled ? 1 : 0);
  config.attribute("maketx:compute_average", 0);
  config.attribute("DateTime", "");
  if (const OIIO::ParamValue* compression = spec.find_attribute("compression")) {
    config.attribute("compression", compression->get_string());
  }
  write_atomically(path, [&](const fs::path& tmp) {
    if (!OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, buffer, tmp.string(), config)) {
      throw InternalError(path + ": cannot write texture: " + one_line(OIIO::geterror()));
    }
  });
}

}  // namespace

void limit_image_io_threads(int threads) {
  if (threads <= 0) return;
  OIIO::attribute("threads", threads);
  // OpenImageIO's exr_threads: the size of OpenEXR's pool, −1 for none (the
  // calling thread compresses). With one thread, none; otherwise the pool
  // overlaps compression with the caller, which waits on it.
  OIIO::attribute("exr_threads", threads == 1 ? -1 : threads);
}

namespace {

/// The header of an image written to `path` as `format` with pixels of `type`:
/// channel names and alpha, colour space, constant stamps, the caller's
/// metadata and the format's compression.
OIIO::ImageSpec output_spec(const std::string& path, Format format, OIIO::TypeDesc type, const Image& image,
                            const ImageWriteOptions& options) {
  OIIO::ImageSpec spec(image.width, image.height, image.channels, type);
  spec.channelnames = channel_names(image, options, path);
  spec.alpha_channel = -1;
  for (int c = 0; c < image.channels; ++c) {
    const std::string n = to_lower(spec.channelnames[c]);
    if (n == "a" || n == "alpha") spec.alpha_channel = c;
  }
  const bool integer = !is_float_type(type);
  const bool managed = !options.data && !options.color_space.empty();
  spec.attribute("oiio:ColorSpace", options.data ? "Raw" : managed ? options.color_space : integer ? "sRGB" : "Linear");
  // OpenImageIO 2.4 keeps no oiio:ColorSpace in an EXR: the name goes in a
  // `colorspace` attribute too.
  if (managed) spec.attribute("colorspace", options.color_space);
  spec.attribute("oiio:UnassociatedAlpha", 1);
  // Byte-identical outputs for golden-file diffs: a constant Software tag (the
  // caller's metadata says which build), and an empty DateTime, which stops
  // the EXR and TIFF writers from stamping the current time into the header.
  spec.attribute("Software", "fluidtex");
  spec.attribute("DateTime", "");
  for (const auto& [name, value] : options.metadata) spec.attribute(name, value);
  switch (format) {
    case Format::Exr: {
      // Linear values with Rec. 709 / sRGB primaries and a D65 white: what
      // the exemplars are linearised to (x, y of red, green, blue, white).
      if (!integer && !options.data && !managed) {
        static const float rec709[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
        spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), rec709);
      }
      std::string name = enum_name(options.compression);
      if (options.compression == ExrCompression::Dwaa || options.compression == ExrCompression::Dwab) {
        name.append(1, ':').append(std::to_string(options.dwa_level));
      }
      spec.attribute("compression", name);
      break;
    }
    case Format::Png: spec.attribute("png:compressionLevel", 6); break;
    case Format::Tiff: spec.attribute("compression", "zip"); break;
  }
  return spec;
}

}  // namespace

void write_image(const std::string& path, const Image& image, const ImageWriteOptions& options) {
  const Format format = format_of(path);
  const OIIO::TypeDesc type = pixel_type(path, format, options.depth);
  if (image.width <= 0 || image.height <= 0 || image.channels <= 0 ||
      image.pixels.size() != static_cast<size_t>(image.width) * image.height * image.channels)
    throw InternalError(path + ": image buffer does not match its " + std::to_string(image.width) + "x" +
                        std::to_string(image.height) + "x" + std::to_string(image.channels) + " size");
  if (format == Format::Png && image.channels > 4)
    throw InternalError(path + ": PNG holds at most 4 channels, got " + std::to_string(image.channels));
  // TIFF could hold tiles, but OpenImageIO pads the partial tiles of the
  // small MIP levels with whatever memory held: the bytes would differ from
  // run to run.
  if (format != Format::Exr && options.layout != TextureLayout::Scanline) {
    throw InputError(path, std::string("a ") + enum_name(options.layout) + " texture is written as .exr");
  }

  const OIIO::ImageSpec spec = output_spec(path, format, type, image, options);
  // Colour in an OpenColorIO space is already encoded as that space says.
  const bool srgb = options.data || options.color_space.empty();

  if (options.layout != TextureLayout::Scanline) {
    write_texture(path, image, spec, type, options.layout);
    return;
  }
  write_atomically(path, [&](const fs::path& tmp) {
    auto out = OIIO::ImageOutput::create(tmp.string());
    if (!out) throw InternalError(path + ": cannot create image writer: " + one_line(OIIO::geterror()));
    if (!out->open(tmp.string(), spec))
      throw InternalError(path + ": cannot write image: " + one_line(out->geterror()));
    bool ok = false;
    if (type == OIIO::TypeDesc::UINT8) {
      const auto data = encode_integer<std::uint8_t>(image, spec.alpha_channel, 255, srgb);
      ok = out->write_image(OIIO::TypeDesc::UINT8, data.data());
    } else if (type == OIIO::TypeDesc::UINT16) {
      const auto data = encode_integer<std::uint16_t>(image, spec.alpha_channel, 65535, srgb);
      ok = out->write_image(OIIO::TypeDesc::UINT16, data.data());
    } else {
      ok = out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data());
    }
    if (!ok || !out->close()) throw InternalError(path + ": cannot write image: " + one_line(out->geterror()));
    // OpenImageIO's PNG writer does not see its stream's write errors: a PNG
    // cut short by a full disk would pass for written. It is read back.
    if (format == Format::Png) {
      const StderrCapture quiet;  // libpng prints what it finds wrong
      auto in = OIIO::ImageInput::open(tmp.string());
      std::vector<std::uint8_t> back(image.pixels.size() * type.size());
      if (!in || !in->read_image(0, 0, 0, image.channels, type, back.data())) {
        (void)OIIO::geterror();
        throw InternalError(path + ": cannot write image: the written PNG does not read back");
      }
    }
  });
}

}  // namespace fluidtex
