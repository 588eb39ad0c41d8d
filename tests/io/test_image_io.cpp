// Image reading and writing (io/image_io.h) through OpenImageIO: round trips
// by format and depth, sRGB encoding, bad inputs, atomic writes, channel
// names, compression, tiled and MIP-mapped textures, determinism.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include "fluidtex/io/image_io.h"
#include "fluidtex/util/error.h"
#include "test_util.h"

namespace fluidtex {
namespace {

using test::list_dir;
using test::read_file;
using test::TempDir;
using test::write_file;

double srgb_encode(double l) {
  l = std::clamp(l, 0.0, 1.0);
  return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
}
double srgb_decode(double s) { return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4); }

/// A deterministic image with values spread over [0, 1]; the last channel of
/// a 2- or 4-channel image is alpha.
Image test_image(int w, int h, int c) {
  Image img{w, h, c, std::vector<float>(static_cast<size_t>(w) * h * c)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < c; ++k) img.at(x, y, k) = static_cast<float>(((x * 7 + y * 13 + k * 29) % 101) / 100.0);
  return img;
}

struct RawImage {  // pixels and spec as OpenImageIO reads them (no conversion)
  OIIO::ImageSpec spec;
  std::vector<float> pixels;
};
RawImage read_raw(const std::string& path) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &config);
  EXPECT_TRUE(in) << OIIO::geterror();
  RawImage raw;
  if (!in) return raw;
  raw.spec = in->spec();
  raw.pixels.resize(raw.spec.image_pixels() * raw.spec.nchannels);
  EXPECT_TRUE(in->read_image(0, 0, 0, raw.spec.nchannels, OIIO::TypeDesc::FLOAT, raw.pixels.data()));
  return raw;
}

void write_raw_png8(const std::string& path, int w, int h, int c, const std::vector<std::uint8_t>& data) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out);
  OIIO::ImageSpec spec(w, h, c, OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:UnassociatedAlpha", 1);
  ASSERT_TRUE(out->open(path, spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, data.data()));
  ASSERT_TRUE(out->close());
}

bool is_alpha(int channels, int c) { return (channels == 2 || channels == 4) && c == channels - 1; }

TEST(ImageIoFullDisk, AnImageWriteOnAFullDiskSaysSoAndLeavesNothing) {
  // A 64 KiB file system (tmpfs; needs the right to mount): OpenEXR, TIFF
  // and PNG fail on it without saying why; the error says the disk is full.
  test::TempDir dir;
  const std::string mount = "mount -t tmpfs -o size=64k tmpfs '" + dir.str() + "' 2>/dev/null";
  if (std::system(mount.c_str()) != 0) GTEST_SKIP() << "cannot mount a small tmpfs here (not root)";
  // Noise no compressor shrinks below the 64 KiB (512² texels).
  Image noise = Image::blank(512, 512, 3);
  std::mt19937 random(7);
  std::uniform_real_distribution<float> value(0.0f, 1.0f);
  for (float& v : noise.pixels) v = value(random);
  for (const char* name : {"atlas.exr", "atlas.tif", "atlas.png"}) {
    SCOPED_TRACE(name);
    ImageWriteOptions write;
    write.compression = ExrCompression::None;
    try {
      write_image(dir.file(name), noise, write);
      ADD_FAILURE() << "wrote to a full disk";
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));  // no partial file, no temporary
  }
  const std::string umount = "umount '" + dir.str() + "'";
  EXPECT_EQ(std::system(umount.c_str()), 0);
}

TEST(ImageIoRoundTrip, ExrFloatIsExact) {
  TempDir dir;
  for (int c : {1, 3, 4}) {  // greyscale stays 1 channel, RGBA keeps alpha
    Image img = test_image(17, 9, c);
    img.pixels[0] = 12.5f;  // HDR values survive
    img.pixels[1 % img.pixels.size()] = 1e-6f;
    const std::string path = dir.file("float" + std::to_string(c) + ".exr");
    write_image(path, img, {PixelDepth::Float, {}});
    const RawImage raw = read_raw(path);
    EXPECT_EQ(raw.spec.width, 17);
    EXPECT_EQ(raw.spec.height, 9);
    EXPECT_EQ(raw.spec.nchannels, c);
    EXPECT_EQ(raw.spec.format, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(raw.spec.get_string_attribute("compression"), "zip");
    EXPECT_EQ(raw.pixels, img.pixels);
    const Image back = read_image(path);
    EXPECT_EQ(back.width, 17);
    EXPECT_EQ(back.height, 9);
    EXPECT_EQ(back.channels, c);
    EXPECT_EQ(back.pixels, img.pixels);
  }
}

TEST(ImageIoRoundTrip, ExrHalfWithinHalfPrecision) {
  TempDir dir;
  for (int c : {1, 3, 4}) {
    Image img = test_image(16, 8, c);
    img.pixels[0] = 3.25f;
    const std::string path = dir.file("half" + std::to_string(c) + ".exr");
    write_image(path, img);
    const RawImage raw = read_raw(path);
    EXPECT_EQ(raw.spec.format, OIIO::TypeDesc::HALF);
    EXPECT_EQ(raw.spec.nchannels, c);
    const Image back = read_image(path);
    ASSERT_EQ(back.pixels.size(), img.pixels.size());
    for (size_t i = 0; i < img.pixels.size(); ++i)
      EXPECT_NEAR(back.pixels[i], img.pixels[i], std::abs(img.pixels[i]) * 0x1p-11 + 1e-7) << i;
  }
}

/// 8/16-bit files: colour sRGB-encoded (alpha linear) within half a
/// quantisation step, both in the file and read back.
void expect_quantised_round_trip(const std::string& ext, OIIO::TypeDesc format, double levels, int w, int h) {
  TempDir dir;
  const double tol = 0.5 / levels + 1e-6;
  for (int c : {1, 3, 4}) {
    SCOPED_TRACE(ext + " with " + std::to_string(c) + " channels");
    const Image img = test_image(w, h, c);
    const std::string path = dir.file("img" + std::to_string(c) + ext);
    write_image(path, img);
    const RawImage raw = read_raw(path);
    EXPECT_EQ(raw.spec.format, format);
    EXPECT_EQ(raw.spec.nchannels, c);
    const Image back = read_image(path);
    ASSERT_EQ(back.channels, c);
    ASSERT_EQ(back.pixels.size(), img.pixels.size());
    for (size_t i = 0; i < img.pixels.size(); ++i) {
      if (is_alpha(c, static_cast<int>(i % c))) {
        EXPECT_NEAR(back.pixels[i], img.pixels[i], tol) << i;
        EXPECT_NEAR(raw.pixels[i], img.pixels[i], tol) << i;
      } else {
        EXPECT_NEAR(srgb_encode(back.pixels[i]), srgb_encode(img.pixels[i]), tol) << i;
        EXPECT_NEAR(raw.pixels[i], srgb_encode(img.pixels[i]), tol) << i;
      }
    }
  }
}

TEST(ImageIoRoundTrip, Png8WithinQuantisation) {
  expect_quantised_round_trip(".png", OIIO::TypeDesc::UINT8, 255, 13, 11);
}

TEST(ImageIoRoundTrip, Tiff16WithinQuantisation) {
  expect_quantised_round_trip(".tif", OIIO::TypeDesc::UINT16, 65535, 10, 12);
}

TEST(ImageIoRoundTrip, FloatTiffAnd16BitPng) {
  TempDir dir;
  const Image img = test_image(8, 8, 3);
  write_image(dir.file("f.tiff"), img, {PixelDepth::Float, {}});
  EXPECT_EQ(read_raw(dir.file("f.tiff")).spec.format, OIIO::TypeDesc::FLOAT);
  EXPECT_EQ(read_image(dir.file("f.tiff")).pixels, img.pixels);
  EXPECT_THROW(write_image(dir.file("h.tif"), img, {PixelDepth::Half, {}}), InputError);

  write_image(dir.file("p16.PNG"), img, {PixelDepth::UInt16, {}});
  EXPECT_EQ(read_raw(dir.file("p16.PNG")).spec.format, OIIO::TypeDesc::UINT16);
  const Image back = read_image(dir.file("p16.PNG"));
  for (size_t i = 0; i < img.pixels.size(); ++i)
    EXPECT_NEAR(srgb_encode(back.pixels[i]), srgb_encode(img.pixels[i]), 0.5 / 65535 + 1e-6);
}

TEST(ImageIoEncoding, SrgbCodeValuesAreExact) {
  TempDir dir;
  Image img{6, 1, 1, {}};
  img.pixels = {0.0f, 1.0f, static_cast<float>(srgb_decode(128.0 / 255)), 0.5f, -1.0f, 7.0f};
  write_image(dir.file("codes.png"), img);
  const RawImage raw = read_raw(dir.file("codes.png"));
  const std::vector<float> expected = {0.0f, 1.0f, 128 / 255.0f, 188 / 255.0f, 0.0f, 1.0f};
  ASSERT_EQ(raw.pixels.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_FLOAT_EQ(raw.pixels[i], expected[i]) << i;

  // Decode then encode gives back the same code values: re-saving an 8-bit
  // image is lossless.
  const Image back = read_image(dir.file("codes.png"));
  write_image(dir.file("codes2.png"), back);
  EXPECT_EQ(read_raw(dir.file("codes2.png")).pixels, raw.pixels);
}

TEST(ImageIoRead, Srgb8BitPngDecodesToLinear) {  // 128 -> 0.2158
  TempDir dir;
  const std::string path = dir.file("grey128.png");
  write_raw_png8(path, 2, 2, 1, {128, 128, 128, 128});
  const Image img = read_image(path);
  EXPECT_EQ(img.channels, 1);
  for (float v : img.pixels) EXPECT_NEAR(v, srgb_decode(128.0 / 255), 1e-7);

  // RGBA: colour decoded, alpha left linear and not premultiplied.
  const std::string rgba = dir.file("rgba.png");
  write_raw_png8(rgba, 1, 1, 4, {128, 255, 0, 128});
  const Image px = read_image(rgba);
  ASSERT_EQ(px.channels, 4);
  EXPECT_NEAR(px.pixels[0], 0.2158, 1e-4);
  EXPECT_FLOAT_EQ(px.pixels[1], 1.0f);
  EXPECT_FLOAT_EQ(px.pixels[2], 0.0f);
  EXPECT_FLOAT_EQ(px.pixels[3], 128 / 255.0f);
}

void expect_input_error_naming(const std::string& path) {
  try {
    (void)read_image(path);
    ADD_FAILURE() << "no error for " << path;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
    EXPECT_NE(e.problem().find("cannot read image"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
}

TEST(ImageIoRead, BadInputsAreInputErrors) {
  TempDir dir;
  expect_input_error_naming(dir.file("missing.png"));

  write_file(dir.file("text.png"), "this is not a png\n");
  expect_input_error_naming(dir.file("text.png"));

  write_image(dir.file("full.png"), test_image(64, 64, 3));
  const std::string bytes = read_file(dir.file("full.png"));
  ASSERT_GT(bytes.size(), 200u);
  write_file(dir.file("truncated.png"), bytes.substr(0, bytes.size() / 2));
  expect_input_error_naming(dir.file("truncated.png"));

  expect_input_error_naming(dir.path().string());  // a folder
}

TEST(ImageIoWrite, UnsupportedExtensionLeavesNothing) {
  TempDir dir;
  const Image img = test_image(4, 4, 3);
  EXPECT_THROW(write_image(dir.file("atlas.bmp"), img), InputError);
  EXPECT_THROW(write_image(dir.file("atlas"), img), InputError);
  EXPECT_THROW(write_image(dir.file("atlas.png"), img, {PixelDepth::Float, {}}), InputError);
  EXPECT_THROW(write_image(dir.file("atlas.exr"), img, {PixelDepth::UInt8, {}}), InputError);
  EXPECT_TRUE(list_dir(dir.path()).empty());
}

TEST(ImageIoWrite, OnlyTargetsRemain) {
  TempDir dir;
  const Image img = test_image(5, 7, 4);
  write_image(dir.file("a.exr"), img);
  write_image(dir.file("b.png"), img);
  write_image(dir.file("c.tif"), img);
  write_image(dir.file("a.exr"), img);  // overwrite
  write_image(dir.file("sub/d.exr"), img);
  EXPECT_EQ(list_dir(dir.path()), (std::vector<std::string>{"a.exr", "b.png", "c.tif", "sub"}));
  EXPECT_EQ(list_dir(dir.path() / "sub"), (std::vector<std::string>{"d.exr"}));
}

TEST(ImageIoWrite, ChannelNamesAreKeptInExr) {
  TempDir dir;
  const Image img = test_image(3, 3, 2);
  write_image(dir.file("uv.exr"), img, {PixelDepth::Float, {"u", "v"}});
  const RawImage raw = read_raw(dir.file("uv.exr"));
  EXPECT_EQ(raw.spec.channelnames, (std::vector<std::string>{"u", "v"}));
}

TEST(ImageIoWrite, EveryExrCompressionReadsBackWithItsName) {
  TempDir dir;
  const Image img = test_image(64, 48, 3);
  for (const std::string& name : enum_choices<ExrCompression>()) {
    ImageWriteOptions o;
    o.compression = parse_enum<ExrCompression>(name, "compression");
    o.dwa_level = 60;
    const std::string path = dir.file(name + ".exr");
    write_image(path, img, o);
    write_image(dir.file(name + ".again.exr"), img, o);
    EXPECT_EQ(read_file(path), read_file(dir.file(name + ".again.exr"))) << name;  // deterministic
    const RawImage raw = read_raw(path);
    EXPECT_EQ(raw.spec.get_string_attribute("compression"), name);
    if (name == "dwaa" || name == "dwab") EXPECT_EQ(raw.spec.get_float_attribute("openexr:dwaCompressionLevel"), 60.0f);
    const Image back = read_image(path);
    ASSERT_EQ(back.pixels.size(), img.pixels.size()) << name;
    double worst = 0.0, sum = 0.0;
    for (std::size_t i = 0; i < img.pixels.size(); ++i) {
      const double e = std::abs(static_cast<double>(back.pixels[i]) - img.pixels[i]);
      worst = std::max(worst, e), sum += e;
    }
    const bool lossy = name == "pxr24" || name == "b44" || name == "b44a" || name == "dwaa" || name == "dwab";
    if (lossy)
      EXPECT_LT(sum / img.pixels.size(), 0.02) << name;  // mean error of a lossy codec on a noisy image
    else
      EXPECT_LT(worst, 1e-3) << name;  // half precision
  }
}

TEST(ImageIoWrite, TiledAndMipmappedTexturesReadBackWithTheirMetadata) {
  TempDir dir;
  const Image img = test_image(200, 120, 3);
  for (const std::string ext : {".exr"}) {
    ImageWriteOptions scanline;
    scanline.metadata = {{"fluidtex:frame", "7"}};
    write_image(dir.file("scan" + ext), img, scanline);
    const Image reference = read_image(dir.file("scan" + ext));
    for (TextureLayout layout : {TextureLayout::Tiled, TextureLayout::Mipmap}) {
      SCOPED_TRACE(ext + " " + enum_name(layout));
      ImageWriteOptions o = scanline;
      o.layout = layout;
      o.compression = ExrCompression::Piz;
      const std::string path = dir.file(std::string(enum_name(layout)) + ext);
      write_image(path, img, o);
      write_image(path + ".again" + ext, img, o);
      EXPECT_EQ(read_file(path), read_file(path + ".again" + ext));  // deterministic
      auto in = OIIO::ImageInput::open(path);
      ASSERT_TRUE(in);
      const OIIO::ImageSpec spec = in->spec();
      EXPECT_EQ(spec.tile_width, 64);
      EXPECT_EQ(spec.tile_height, 64);
      int levels = 1;
      while (in->seek_subimage(0, levels)) ++levels;
      // 200x120, 100x60, 50x30, 25x15, 12x7, 6x3, 3x1, 1x1.
      EXPECT_EQ(levels, layout == TextureLayout::Mipmap ? 8 : 1);
      EXPECT_EQ(spec.get_string_attribute("fluidtex:frame"), "7");
      EXPECT_EQ(spec.get_string_attribute("oiio:ColorSpace"), "Linear");
      EXPECT_EQ(spec.get_string_attribute("DateTime"), "");  // no time stamp: reruns give the same bytes
      EXPECT_EQ(spec.get_string_attribute("compression"), "piz");
      EXPECT_NE(spec.find_attribute("chromaticities"), nullptr);
      // The top level holds exactly the scanline file's pixels.
      const Image back = read_image(path);
      ASSERT_EQ(back.pixels.size(), reference.pixels.size());
      EXPECT_TRUE(back.pixels == reference.pixels);
    }
  }
  ImageWriteOptions mip;
  mip.layout = TextureLayout::Mipmap;
  for (const char* name : {"no.png", "no.tif"}) {
    EXPECT_THROW(write_image(dir.file(name), img, mip), InputError);
    EXPECT_FALSE(std::filesystem::exists(dir.file(name)));
  }
}

TEST(ImageIoDeterminism, SameImageSameBytes) {
  TempDir dir;
  const Image img = test_image(33, 21, 4);
  for (const std::string ext : {".exr", ".png", ".tif"}) {
    write_image(dir.file("one" + ext), img);
    write_image(dir.file("two" + ext), img);
    const std::string first = read_file(dir.file("one" + ext));
    EXPECT_FALSE(first.empty());
    EXPECT_EQ(first, read_file(dir.file("two" + ext))) << ext;
    write_image(dir.file("one" + ext), img);
    EXPECT_EQ(first, read_file(dir.file("one" + ext))) << ext;
    // Nothing time-dependent in the header (two writes within one second
    // would not reveal a timestamp).
    const RawImage raw = read_raw(dir.file("one" + ext));
    EXPECT_EQ(raw.spec.find_attribute("DateTime"), nullptr) << ext;
  }
  write_image(dir.file("f1.exr"), img, {PixelDepth::Float, {}});
  write_image(dir.file("f2.exr"), img, {PixelDepth::Float, {}});
  EXPECT_EQ(read_file(dir.file("f1.exr")), read_file(dir.file("f2.exr")));
}

}  // namespace
}  // namespace fluidtex
