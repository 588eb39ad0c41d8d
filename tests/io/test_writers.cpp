// Tests for the output writers: images (OpenImageIO), UV meshes (OBJ/PLY,
// read back through OpenMesh) and stats.jsonl.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "fluidtex/io/image_io.h"
#include "fluidtex/io/mesh_io.h"
#include "fluidtex/io/stats.h"
#include "fluidtex/io/uv_mesh_io.h"
#include "fluidtex/util/error.h"
#include "test_util.h"

namespace fluidtex {
namespace {

using test::list_dir;
using test::read_file;
using test::TempDir;
using test::write_file;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

// ---------------------------------------------------------------------------
// Images
// ---------------------------------------------------------------------------

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

// ---------------------------------------------------------------------------
// UV meshes
// ---------------------------------------------------------------------------

/// A 2x1 quad strip split into two charts along the edge 1-4 (a seam):
///   3---4---5
///   | A | B |
///   0---1---2
/// Vertices 1 and 4 carry one uv per chart: 8 distinct (vertex, uv) pairs.
UVMesh seam_mesh() {
  UVMesh m;
  m.positions = {Vec3(0, 0, 0),           Vec3(1, 0, 0),   Vec3(2, 0, 0.25),
                 Vec3(0, 1, 0.123456789), Vec3(1, 1, 0.5), Vec3(2, 1, -1e-3)};
  m.normals.assign(6, Vec3(0, 0, 1));
  m.normals[2] = Vec3(0.6, 0, 0.8);
  m.triangles = {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}};
  m.uvs = {Vec2(0.0, 0.0), Vec2(0.4, 0.0), Vec2(0.4, 0.4), Vec2(0.0, 0.4),   // chart A
           Vec2(0.6, 0.6), Vec2(1.0, 0.6), Vec2(1.0, 1.0), Vec2(0.6, 1.0)};  // chart B
  m.uv_triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
  return m;
}

using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;

TEST(UvMeshWriterObj, RoundTripThroughOpenMesh) {
  TempDir dir;
  const UVMesh m = seam_mesh();
  const std::string path = dir.file("frame.obj");
  write_uv_mesh_obj(path, m, "atlas_0001.png");
  EXPECT_EQ(list_dir(dir.path()), (std::vector<std::string>{"frame.mtl", "frame.obj"}));

  OMesh om;
  om.request_halfedge_texcoords2D();
  om.request_vertex_normals();
  OpenMesh::IO::Options opt = OpenMesh::IO::Options::FaceTexCoord | OpenMesh::IO::Options::VertexNormal;
  ASSERT_TRUE(OpenMesh::IO::read_mesh(om, path, opt));
  ASSERT_EQ(om.n_vertices(), m.positions.size());
  ASSERT_EQ(om.n_faces(), m.triangles.size());
  EXPECT_TRUE(opt.face_has_texcoord());
  for (size_t v = 0; v < m.positions.size(); ++v) {
    const auto p = om.point(OMesh::VertexHandle(static_cast<int>(v)));
    for (int i = 0; i < 3; ++i) EXPECT_EQ(p[i], static_cast<float>(m.positions[v][i])) << v;
  }
  for (size_t f = 0; f < m.triangles.size(); ++f) {
    int corners = 0;
    for (auto h : om.fh_range(OMesh::FaceHandle(static_cast<int>(f)))) {
      const int v = om.to_vertex_handle(h).idx();
      const auto& tri = m.triangles[f];
      const int k = static_cast<int>(std::find(tri.begin(), tri.end(), v) - tri.begin());
      ASSERT_LT(k, 3) << "face " << f << " lost vertex " << v;
      const Vec2& uv = m.uvs[m.uv_triangles[f][k]];
      const auto t = om.texcoord2D(h);
      EXPECT_EQ(t[0], static_cast<float>(uv.x())) << f << "/" << k;
      EXPECT_EQ(t[1], static_cast<float>(uv.y())) << f << "/" << k;
      ++corners;
    }
    EXPECT_EQ(corners, 3);
  }
}

TEST(UvMeshWriterObj, FaceTripletsAndMaterial) {
  TempDir dir;
  const UVMesh m = seam_mesh();
  const std::string path = dir.file("frame.obj");
  write_uv_mesh_obj(path, m, (dir.path() / "atlas_0001.png").string());
  std::vector<std::string> face_lines;
  int v = 0, vt = 0, vn = 0;
  bool mtllib = false, usemtl = false;
  for (const std::string& line : lines_of(read_file(path))) {
    if (line.rfind("v ", 0) == 0) ++v;
    if (line.rfind("vt ", 0) == 0) ++vt;
    if (line.rfind("vn ", 0) == 0) ++vn;
    if (line == "mtllib frame.mtl") mtllib = true;
    if (line == "usemtl fluidtex_atlas") usemtl = true;
    if (line.rfind("f ", 0) == 0) face_lines.push_back(line);
  }
  EXPECT_EQ(v, 6);
  EXPECT_EQ(vt, 8);
  EXPECT_EQ(vn, 6);
  EXPECT_TRUE(mtllib);
  EXPECT_TRUE(usemtl);
  ASSERT_EQ(face_lines.size(), m.triangles.size());
  for (size_t f = 0; f < face_lines.size(); ++f) {
    std::istringstream in(face_lines[f].substr(2));
    for (int k = 0; k < 3; ++k) {
      int a = 0, b = 0, c = 0;
      char s1 = 0, s2 = 0;
      in >> a >> s1 >> b >> s2 >> c;
      EXPECT_EQ(s1, '/');
      EXPECT_EQ(s2, '/');
      EXPECT_EQ(a, m.triangles[f][k] + 1) << face_lines[f];
      EXPECT_EQ(b, m.uv_triangles[f][k] + 1) << face_lines[f];
      EXPECT_EQ(c, m.triangles[f][k] + 1) << face_lines[f];
    }
  }
  const std::string mtl = read_file(dir.file("frame.mtl"));
  EXPECT_NE(mtl.find("newmtl fluidtex_atlas\n"), std::string::npos);
  EXPECT_NE(mtl.find("map_Kd atlas_0001.png\n"), std::string::npos) << mtl;  // made relative
  EXPECT_EQ(mtl.find("disp"), std::string::npos) << mtl;
  EXPECT_EQ(mtl.find("norm"), std::string::npos) << mtl;

  // Height and normal atlases: disp, bump with its multiplier, norm.
  MaterialMaps maps((dir.path() / "atlas_0001.exr").string());
  maps.displacement = (dir.path() / "maps" / "height_0001.exr").string();
  maps.normal = "normal_0001.exr";
  maps.bump_height = 0.0125;
  write_uv_mesh_obj(path, m, maps);
  const std::vector<std::string> lines = lines_of(read_file(dir.file("frame.mtl")));
  for (const char* expected : {"map_Kd atlas_0001.exr", "disp maps/height_0001.exr",
                               "bump -bm 0.0125 maps/height_0001.exr", "norm normal_0001.exr"}) {
    EXPECT_NE(std::find(lines.begin(), lines.end(), expected), lines.end()) << expected;
  }
}

TEST(UvMeshWriterObj, PositionsKeepFloatPrecision) {
  TempDir dir;
  write_uv_mesh(dir.file("m.OBJ"), seam_mesh());
  const std::string text = read_file(dir.file("m.OBJ"));
  EXPECT_NE(text.find("v 0 1 0.12345679\n"), std::string::npos) << text;
  EXPECT_NE(text.find("v 2 1 -0.001\n"), std::string::npos) << text;
  EXPECT_NE(text.find("vt 0.4 0\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("mtllib"), std::string::npos);
}

TEST(UvMeshWriterPly, CarriesVelocitiesForMotionBlur) {
  TempDir dir;
  UVMesh m = seam_mesh();
  for (std::size_t v = 0; v < m.positions.size(); ++v) m.velocities.emplace_back(0.5 * v, -1.0, 0.25);
  const std::string path = dir.file("frame.ply");
  write_uv_mesh_ply(path, m);
  EXPECT_NE(read_file(path).find("property float v\nproperty float vx\nproperty float vy\nproperty float vz\n"),
            std::string::npos);
  // fluidtex's own reader takes them as the vertices' velocities (seam
  // copies of a vertex carry its velocity).
  ReadOptions read;
  read.clean = false;
  const FrameMesh back = read_frame(path, read);
  ASSERT_EQ(back.velocities.size(), back.positions.size());
  for (std::size_t i = 0; i < back.positions.size(); ++i) {
    const auto same_place = [&](const Vec3& p) { return p.cast<float>().cast<double>() == back.positions[i]; };
    const auto v = std::find_if(m.positions.begin(), m.positions.end(), same_place) - m.positions.begin();
    ASSERT_LT(v, static_cast<long>(m.positions.size())) << i;
    EXPECT_EQ(back.velocities[i], m.velocities[v].cast<float>().cast<double>()) << i;
  }
  // Without velocities the header is the plain one.
  write_uv_mesh_ply(dir.file("plain.ply"), seam_mesh());
  EXPECT_EQ(read_file(dir.file("plain.ply")).find("vx"), std::string::npos);
}

TEST(UvMeshWriterPly, RoundTripThroughOpenMesh) {
  TempDir dir;
  const UVMesh m = seam_mesh();
  const std::string path = dir.file("frame.ply");
  write_uv_mesh_ply(path, m);
  EXPECT_EQ(read_file(path).rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);

  // Expected split: distinct (vertex, uv index) pairs, sorted.
  std::vector<std::pair<int, int>> pairs;
  for (size_t f = 0; f < m.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) pairs.emplace_back(m.triangles[f][k], m.uv_triangles[f][k]);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  ASSERT_EQ(pairs.size(), 8u);

  OMesh om;
  om.request_vertex_texcoords2D();
  om.request_vertex_normals();
  OpenMesh::IO::Options opt =
      OpenMesh::IO::Options::VertexTexCoord | OpenMesh::IO::Options::VertexNormal | OpenMesh::IO::Options::Binary;
  ASSERT_TRUE(OpenMesh::IO::read_mesh(om, path, opt));
  ASSERT_EQ(om.n_vertices(), pairs.size());
  ASSERT_EQ(om.n_faces(), m.triangles.size());
  EXPECT_TRUE(opt.vertex_has_texcoord());
  EXPECT_TRUE(opt.vertex_has_normal());
  for (size_t i = 0; i < pairs.size(); ++i) {
    const OMesh::VertexHandle vh(static_cast<int>(i));
    const auto [v, uvi] = pairs[i];
    const auto p = om.point(vh);
    const auto n = om.normal(vh);
    const auto t = om.texcoord2D(vh);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(p[c], static_cast<float>(m.positions[v][c])) << i;
      EXPECT_EQ(n[c], static_cast<float>(m.normals[v][c])) << i;
    }
    EXPECT_EQ(t[0], static_cast<float>(m.uvs[uvi].x())) << i;
    EXPECT_EQ(t[1], static_cast<float>(m.uvs[uvi].y())) << i;
  }
  // Each face's corners carry the uv of that corner.
  for (size_t f = 0; f < m.triangles.size(); ++f)
    for (auto vh : om.fv_range(OMesh::FaceHandle(static_cast<int>(f)))) {
      const auto [v, uvi] = pairs[vh.idx()];
      const auto& tri = m.triangles[f];
      const int k = static_cast<int>(std::find(tri.begin(), tri.end(), v) - tri.begin());
      ASSERT_LT(k, 3);
      EXPECT_EQ(m.uv_triangles[f][k], uvi);
    }
}

/// Each corner of `a` and of `b` at the same place with the same uv (to
/// float precision): the same textured surface, whatever the vertex split.
void expect_same_corners(const UVMesh& a, const UVMesh& b) {
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  for (std::size_t f = 0; f < a.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(a.positions[a.triangles[f][k]].cast<float>(), b.positions[b.triangles[f][k]].cast<float>()) << f;
      EXPECT_EQ(a.uvs[a.uv_triangles[f][k]].cast<float>(), b.uvs[b.uv_triangles[f][k]].cast<float>()) << f;
      if (!a.normals.empty() && !b.normals.empty())
        EXPECT_EQ(a.normals[a.triangles[f][k]].cast<float>(), b.normals[b.triangles[f][k]].cast<float>()) << f;
    }
}

TEST(UvMeshReader, ReadsThePlyAndTheObjTheWritersWrite) {
  TempDir dir;
  UVMesh m = seam_mesh();
  for (std::size_t v = 0; v < m.positions.size(); ++v) m.velocities.emplace_back(0.5 * v, -1.0, 0.25);
  write_uv_mesh(dir.file("m.ply"), m);
  write_uv_mesh(dir.file("m.obj"), m);
  const UVMesh ply = read_uv_mesh(dir.file("m.ply")), obj = read_uv_mesh(dir.file("m.obj"));
  expect_same_corners(m, ply);
  expect_same_corners(m, obj);
  EXPECT_EQ(ply.positions.size(), 8u);  // split at the seam: one vertex per (vertex, uv)
  ASSERT_EQ(ply.velocities.size(), ply.positions.size());
  for (std::size_t f = 0; f < m.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(ply.velocities[ply.triangles[f][k]], m.velocities[m.triangles[f][k]].cast<float>().cast<double>());
  // A non-manifold frame (three faces on an edge) passes through as written.
  UVMesh fan;
  fan.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1)};
  fan.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  fan.uvs = {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1), Vec2(0.5, 0.5), Vec2(1, 1)};
  fan.uv_triangles = fan.triangles;
  write_uv_mesh(dir.file("fan.ply"), fan);
  expect_same_corners(fan, read_uv_mesh(dir.file("fan.ply")));
}

TEST(UvMeshReader, RefusesWhatIsNotAUvMeshInOneLine) {
  TempDir dir;
  write_uv_mesh(dir.file("m.ply"), seam_mesh());
  const std::string good = read_file(dir.file("m.ply"));
  auto refusal = [&](const std::string& name, const std::string& bytes) {
    test::write_file(dir.path() / name, bytes);
    try {
      read_uv_mesh(dir.file(name));
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      EXPECT_NE(what.find(name), std::string::npos) << what;
      return what;
    }
    ADD_FAILURE() << name << " was read";
    return std::string();
  };
  EXPECT_NE(refusal("short.ply", good.substr(0, good.size() - 5)).find("truncated"), std::string::npos);
  EXPECT_NE(refusal("body.ply", good.substr(0, good.find("end_header\n") + 20)).find("truncated"), std::string::npos);
  // An input frame (positions and velocities, no uv) is not a UV mesh.
  const std::string frame =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nproperty float vx\nproperty float vy\nproperty float vz\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n" +
      std::string(3 * 6 * 4, '\0') + std::string("\x03\0\0\0\0\x01\0\0\0\x02\0\0\0", 13);
  EXPECT_NE(refusal("frame.ply", frame).find("no texture coordinates"), std::string::npos);
  std::string far = good;
  far[far.size() - 4] = '\x7f';  // the last corner's index, far past the vertices
  EXPECT_NE(refusal("far.ply", far).find("names vertex"), std::string::npos);
  std::string nan = good;
  const std::size_t body = nan.find("end_header\n") + 11;
  for (int i = 0; i < 4; ++i) nan[body + i] = "\x00\x00\xc0\x7f"[i];  // the first x: a quiet NaN
  EXPECT_NE(refusal("nan.ply", nan).find("non-finite"), std::string::npos);
  EXPECT_NE(refusal("ascii.ply", "ply\nformat ascii 1.0\nelement vertex 0\nend_header\n").find("binary"),
            std::string::npos);
  EXPECT_NE(refusal("m.stl", good).find("use .obj or .ply"), std::string::npos);
  EXPECT_THROW(read_uv_mesh(dir.file("missing.ply")), InputError);
}

TEST(UvMeshWriterPly, NonManifoldFramePassesThrough) {
  // Three triangles on one edge (non-manifold) and an isolated vertex.
  UVMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(5, 5, 5)};
  m.normals.assign(6, Vec3(0, 0, 1));
  m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  m.uvs = {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1), Vec2(0.5, 0.5), Vec2(1, 1)};
  m.uv_triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  TempDir dir;
  write_uv_mesh(dir.file("nm.ply"), m);
  write_uv_mesh(dir.file("nm.obj"), m);
  const std::string ply = read_file(dir.file("nm.ply"));
  EXPECT_NE(ply.find("element vertex 6\n"), std::string::npos);  // 5 used + 1 isolated
  EXPECT_NE(ply.find("element face 3\n"), std::string::npos);
  const size_t header = ply.find("end_header\n") + 11;
  EXPECT_EQ(ply.size(), header + 6 * 8 * 4 + 3 * 13);
  const std::string obj = read_file(dir.file("nm.obj"));
  const auto obj_lines = lines_of(obj);
  EXPECT_EQ(
      std::count_if(obj_lines.begin(), obj_lines.end(), [](const std::string& l) { return l.rfind("f ", 0) == 0; }), 3);
}

TEST(UvMeshWriterErrors, UnsupportedExtensionAndBadMesh) {
  TempDir dir;
  EXPECT_THROW(write_uv_mesh(dir.file("frame.stl"), seam_mesh()), InputError);
  UVMesh bad = seam_mesh();
  bad.triangles[0][1] = 42;
  EXPECT_THROW(write_uv_mesh(dir.file("bad.obj"), bad), InternalError);
  bad = seam_mesh();
  bad.uv_triangles.pop_back();
  EXPECT_THROW(write_uv_mesh(dir.file("bad.ply"), bad), InternalError);
  EXPECT_TRUE(list_dir(dir.path()).empty());
}

TEST(UvMeshWriterDeterminism, SameMeshSameBytes) {
  TempDir dir;
  for (const std::string ext : {".obj", ".ply"}) {
    write_uv_mesh(dir.file("a" + ext), seam_mesh());
    write_uv_mesh(dir.file("b" + ext), seam_mesh());
    EXPECT_EQ(read_file(dir.file("a" + ext)), read_file(dir.file("b" + ext)));
  }
  EXPECT_EQ(list_dir(dir.path()), (std::vector<std::string>{"a.obj", "a.ply", "b.obj", "b.ply"}));
}

// ---------------------------------------------------------------------------
// Stats
// ---------------------------------------------------------------------------

FrameStats sample_stats(int frame) {
  FrameStats s;
  s.frame = frame;
  s.vertices = 1234;
  s.faces = 2400;
  s.patches = {1, 2, 3, 4};
  s.seconds = {{"advect", 0.25}, {"synthesis", 1.5}, {"pack", 0.1}};
  s.uncovered_fraction = 0.003;
  s.extra = {{"packing_efficiency", 0.7}, {"texels_per_second", 1e20}};
  return s;
}

TEST(StatsJson, ExactLine) {
  EXPECT_EQ(to_json_line(sample_stats(7)),
            "{\"frame\":7,\"vertices\":1234,\"faces\":2400,"
            "\"patches\":{\"fading_in\":1,\"active\":2,\"fading_out_distorted\":3,"
            "\"fading_out_close\":4},"
            "\"seconds\":{\"advect\":0.25,\"synthesis\":1.5,\"pack\":0.1},"
            "\"uncovered_fraction\":0.003,"
            "\"packing_efficiency\":0.7,\"texels_per_second\":1e+20}");
}

TEST(StatsJson, NonFiniteIsNullAndKeysAreEscaped) {
  FrameStats s;
  s.frame = -1;
  s.uncovered_fraction = std::numeric_limits<double>::quiet_NaN();
  s.seconds = {{"a\"b\\c", std::numeric_limits<double>::infinity()}};
  s.extra = {{"tab\there\nnew\x01", -0.0}, {"small", 1.0 / 3.0}};
  EXPECT_EQ(to_json_line(s),
            "{\"frame\":-1,\"vertices\":0,\"faces\":0,"
            "\"patches\":{\"fading_in\":0,\"active\":0,\"fading_out_distorted\":0,"
            "\"fading_out_close\":0},"
            "\"seconds\":{\"a\\\"b\\\\c\":null},\"uncovered_fraction\":null,"
            "\"tab\\there\\nnew\\u0001\":-0,\"small\":0.3333333333333333}");
}

TEST(StatsWriter, AddRewritesAndAppendExistingKeepsLines) {
  TempDir dir;
  const std::string path = dir.file("stats.jsonl");
  {
    StatsWriter w(path);
    w.add(sample_stats(1));
    w.add(sample_stats(2));
    EXPECT_EQ(read_file(path), to_json_line(sample_stats(1)) + "\n" + to_json_line(sample_stats(2)) + "\n");
  }
  {
    StatsWriter w(path, /*append_existing=*/true);
    w.add(sample_stats(3));
    const auto lines = lines_of(read_file(path));
    ASSERT_EQ(lines.size(), 3u);
    EXPECT_EQ(lines[0], to_json_line(sample_stats(1)));
    EXPECT_EQ(lines[2], to_json_line(sample_stats(3)));
    // A resumed frame replaces its old line instead of listing it twice.
    FrameStats redo = sample_stats(2);
    redo.faces = 99;
    w.add(redo);
    const auto again = lines_of(read_file(path));
    ASSERT_EQ(again.size(), 3u);
    EXPECT_EQ(again[1], to_json_line(redo));
  }
  EXPECT_EQ(list_dir(dir.path()), (std::vector<std::string>{"stats.jsonl"}));
  {
    StatsWriter w(path);  // a fresh run starts a fresh file
    EXPECT_EQ(read_file(path), "");
    w.add(sample_stats(10));
    EXPECT_EQ(lines_of(read_file(path)).size(), 1u);
  }
  StatsWriter missing(dir.file("new/stats.jsonl"), true);  // nothing to resume from
  missing.add(sample_stats(0));
  EXPECT_EQ(lines_of(read_file(dir.file("new/stats.jsonl"))).size(), 1u);
}

}  // namespace
}  // namespace fluidtex
