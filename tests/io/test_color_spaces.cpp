// Colour management (io/color_spaces.h) through a small OpenColorIO config
// written here: two linear spaces a matrix apart. Pixel values are checked
// exactly: the exemplar is converted once into the working space, the atlas
// once into the output space.
#include <gtest/gtest.h>

#include <array>
#include <string>

#include "color_fixtures.h"
#include "fluidtex/io/color_spaces.h"
#include "fluidtex/io/image_io.h"
#include "fluidtex/util/error.h"
#include "test_util.h"

namespace fluidtex {
namespace {

TEST(ColorSpaces, TheExemplarIsConvertedOnceIntoTheWorkingSpaceAndTheAtlasOnceOut) {
  test::TempDir dir;
  test::write_file(dir.path() / "test.ocio", test::kTwoSpaceConfig);
  test::write_swatch(dir.file("wide.exr"), "wide", true);
  ColorSpaceOptions o;
  o.config = dir.file("test.ocio");
  o.working = "lin_a";
  const ColorSpaces colors(o);  // the file names its space: wide
  ASSERT_TRUE(colors.managed());
  std::string warning;
  const Image working = colors.read_exemplar(dir.file("wide.exr"), warning);
  EXPECT_TRUE(warning.empty()) << warning;
  const std::array<float, 3> expected = test::wide_to_lin_a(0.2f, 0.4f, 0.8f);
  for (std::size_t i = 0; i < 256; ++i) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(working.pixel(i)[c], expected[c], 1e-6) << c;
    EXPECT_EQ(working.pixel(i)[3], 0.5f);  // alpha is never converted
  }
  // Out to wide again: the original values; to the working space itself:
  // untouched.
  o.output = "wide";
  const Image back = ColorSpaces(o).to_output(working);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(back.pixel(5)[c], (std::array<float, 3>{0.2f, 0.4f, 0.8f})[c], 1e-6);
  EXPECT_EQ(colors.to_output(working).pixels, working.pixels);
  // --exemplar-colorspace wins over the file's name.
  o.exemplar = "lin_a";
  const Image as_given = ColorSpaces(o).read_exemplar(dir.file("wide.exr"), warning);
  EXPECT_NEAR(as_given.pixel(0)[0], 0.2f, 1e-7);
}

TEST(ColorSpaces, AnUnknownNameIsOneLineListingTheConfigsSpaces) {
  test::TempDir dir;
  test::write_file(dir.path() / "test.ocio", test::kTwoSpaceConfig);
  ColorSpaceOptions o;
  o.config = dir.file("test.ocio");
  o.working = "ACEScg";
  try {
    ColorSpaces{o};
    ADD_FAILURE() << "accepted an unknown space";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_NE(what.find("--working-colorspace"), std::string::npos) << what;
    EXPECT_NE(what.find("'ACEScg' is not a colour space of " + dir.file("test.ocio") + " (its spaces: lin_a, wide)"),
              std::string::npos)
        << what;
  }
  // No linear Rec. 709 space to default the working space to: name one.
  o.working.clear();
  o.output = "wide";
  EXPECT_THROW(ColorSpaces{o}, InputError);
  // A config that cannot be read, and an exemplar naming no space the
  // config has.
  o.config = dir.file("missing.ocio");
  o.working = "lin_a";
  EXPECT_THROW(ColorSpaces{o}, InputError);
  o.config = dir.file("test.ocio");
  test::write_swatch(dir.file("aces.exr"), "ACEScg", false);
  std::string warning;
  EXPECT_THROW(ColorSpaces(o).read_exemplar(dir.file("aces.exr"), warning), InputError);
}

TEST(ColorSpaces, UnmanagedTheRulesApplyAndAnUnknownSpaceIsWarnedOf) {
  test::TempDir dir;
  test::write_swatch(dir.file("aces.exr"), "ACEScg", false);
  const ColorSpaces colors;
  EXPECT_FALSE(colors.managed());
  std::string warning;
  const Image image = colors.read_exemplar(dir.file("aces.exr"), warning);
  EXPECT_EQ(image.pixel(0)[0], 0.2f);  // as stored: float files are linear
  EXPECT_NE(warning.find("names the colour space 'ACEScg'"), std::string::npos) << warning;
  test::write_swatch(dir.file("linear.exr"), "", false);  // write_image's own tag: Linear
  colors.read_exemplar(dir.file("linear.exr"), warning);
  EXPECT_TRUE(warning.empty()) << warning;
}

}  // namespace
}  // namespace fluidtex
