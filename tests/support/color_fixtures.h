// A small OpenColorIO config for the colour tests (test_color_spaces,
// test_pipeline): two linear spaces a matrix apart, and a one-colour EXR.
#pragma once

#include <array>
#include <string>

#include "fluidtex/io/image_io.h"

namespace fluidtex::test {

/// `lin_a` (the reference) and `wide`, whose values go to lin_a through kWide.
inline constexpr const char* kTwoSpaceConfig = R"(ocio_profile_version: 2

roles:
  default: lin_a
  scene_linear: lin_a

displays:
  sRGB:
    - !<View> {name: Raw, colorspace: lin_a}
active_displays: [sRGB]
active_views: [Raw]

colorspaces:
  - !<ColorSpace>
    name: lin_a
    family: linear
    bitdepth: 32f
    isdata: false

  - !<ColorSpace>
    name: wide
    family: linear
    bitdepth: 32f
    isdata: false
    to_scene_reference: !<MatrixTransform> {matrix: [0.5, 0.25, 0.25, 0, 0.125, 0.75, 0.125, 0, 0, 0.25, 0.75, 0, 0, 0, 0, 1]}
)";

/// wide → lin_a of the colour (r, g, b), as the matrix above says.
inline std::array<float, 3> wide_to_lin_a(float r, float g, float b) {
  return {0.5f * r + 0.25f * g + 0.25f * b, 0.125f * r + 0.75f * g + 0.125f * b, 0.25f * g + 0.75f * b};
}

/// A 16×16 float EXR of one colour (0.2, 0.4, 0.8) (and alpha 0.5 when `alpha`), naming `space`.
inline void write_swatch(const std::string& path, const std::string& space, bool alpha) {
  Image image = Image::blank(16, 16, alpha ? 4 : 3);
  for (std::size_t i = 0; i < 256; ++i) {
    float* p = image.pixel(i);
    p[0] = 0.2f, p[1] = 0.4f, p[2] = 0.8f;
    if (alpha) p[3] = 0.5f;
  }
  ImageWriteOptions write;
  write.depth = PixelDepth::Float;
  write.color_space = space;
  write_image(path, image, write);
}

}  // namespace fluidtex::test
