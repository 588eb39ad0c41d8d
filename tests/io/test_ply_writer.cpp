// The one PLY form fluidtex writes (io/ply_writer.h): the exact header and
// body, and values out of the header's order refused before anything is
// written.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>

#include "fluidtex/io/ply_writer.h"
#include "fluidtex/util/error.h"
#include "test_util.h"

namespace fluidtex {
namespace {

using T = PlyWriter::Type;

TEST(PlyWriter, HeaderAndBodyAreExact) {
  const test::TempDir dir;
  PlyWriter ply({"made by a test", "fps=24"}, {{"x"}, {"red", T::UChar}}, 3, 1);
  for (int v = 0; v < 3; ++v) {
    ply.put(0.5 * v);
    ply.put(std::uint8_t(200 + v));
  }
  ply.put_triangle(0, 1, 2);
  ply.write(dir.file("m.ply"));
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment made by a test\ncomment fps=24\nelement vertex 3\n"
      "property float x\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string bytes = test::read_file(dir.file("m.ply"));
  ASSERT_EQ(bytes.size(), header.size() + 3 * 5 + 13);
  EXPECT_EQ(bytes.substr(0, header.size()), header);
  float x = 0.0f;
  std::memcpy(&x, bytes.data() + header.size() + 5, 4);
  EXPECT_EQ(x, 0.5f);
  EXPECT_EQ(static_cast<unsigned char>(bytes[header.size() + 9]), 201);
  const std::string face = bytes.substr(header.size() + 15);
  EXPECT_EQ(face, std::string("\x03\x00\x00\x00\x00\x01\x00\x00\x00\x02\x00\x00\x00", 13));
}

TEST(PlyWriter, ValuesOutOfTheHeadersOrderAreRefusedAndNothingIsWritten) {
  const test::TempDir dir;
  PlyWriter wrong_type({}, {{"x"}, {"red", T::UChar}}, 1, 0);
  EXPECT_THROW(wrong_type.put(std::uint8_t{1}), InternalError);
  PlyWriter too_many({}, {{"x"}}, 1, 0);
  too_many.put(1.0);
  EXPECT_THROW(too_many.put(2.0), InternalError);
  EXPECT_THROW(too_many.put_triangle(0, 0, 0), InternalError);
  PlyWriter too_few({}, {{"x"}}, 2, 0);
  too_few.put(1.0);
  EXPECT_THROW(too_few.write(dir.file("short.ply")), InternalError);
  EXPECT_FALSE(std::filesystem::exists(dir.file("short.ply")));
}

}  // namespace
}  // namespace fluidtex
