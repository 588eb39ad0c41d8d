#include "fluidtex/job/debug_views.h"

#include <cstdint>

#include "fluidtex/io/ply_writer.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/random.h"

namespace fluidtex {

namespace {

using Rgb = std::array<unsigned char, 3>;

/// Float xyz, uchar rgb and optional faces.
void write_colored_ply(const std::string& path, const std::vector<Vec3>& positions, const std::vector<Rgb>& colors,
                       const std::vector<Tri>& triangles) {
  using T = PlyWriter::Type;
  PlyWriter ply({"fluidtex debug view"},
                {{"x"}, {"y"}, {"z"}, {"red", T::UChar}, {"green", T::UChar}, {"blue", T::UChar}}, positions.size(),
                triangles.size());
  for (std::size_t i = 0; i < positions.size(); ++i) {
    for (int k = 0; k < 3; ++k) ply.put(positions[i][k]);
    for (const unsigned char c : colors[i]) ply.put(std::uint8_t{c});
  }
  for (const Tri& t : triangles) {
    ply.put_triangle(static_cast<std::uint32_t>(t[0]), static_cast<std::uint32_t>(t[1]),
                     static_cast<std::uint32_t>(t[2]));
  }
  ply.write(path);
}

}  // namespace

void write_patch_view(const std::string& path, const std::vector<Patch>& patches) {
  std::vector<Vec3> positions;
  std::vector<Rgb> colors;
  std::vector<Tri> triangles;
  for (const Patch& p : patches) {
    const int offset = static_cast<int>(positions.size());
    const Rgb color = id_color(p.id);
    positions.insert(positions.end(), p.positions.begin(), p.positions.end());
    colors.insert(colors.end(), p.positions.size(), color);
    for (const Tri& t : p.triangles) triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  }
  write_colored_ply(path, positions, colors, triangles);
}

void write_disk_view(const std::string& path, const std::vector<Patch>& patches, int frame) {
  std::vector<Vec3> positions;
  std::vector<Rgb> colors;
  for (const Patch& p : patches) {
    positions.push_back(p.centre.point.position);
    if (is_fading_out(p.state))
      colors.push_back({220, 30, 30});
    else if (p.created_frame == frame)
      colors.push_back({40, 90, 230});
    else
      colors.push_back({30, 200, 60});
  }
  write_colored_ply(path, positions, colors, {});
}

}  // namespace fluidtex
