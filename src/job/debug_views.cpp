#include "fluidtex/job/debug_views.h"

#include <fstream>

#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/random.h"

namespace fluidtex {

namespace {

using Rgb = std::array<unsigned char, 3>;

/// Binary little-endian PLY with float xyz, uchar rgb and optional faces.
void write_colored_ply(const std::string& path, const std::vector<Vec3>& positions, const std::vector<Rgb>& colors,
                       const std::vector<Tri>& triangles) {
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out << "ply\nformat binary_little_endian 1.0\ncomment fluidtex debug view\n"
        << "element vertex " << positions.size() << "\n"
        << "property float x\nproperty float y\nproperty float z\n"
        << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
        << "element face " << triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (std::size_t i = 0; i < positions.size(); ++i) {
      const float p[3] = {static_cast<float>(positions[i].x()), static_cast<float>(positions[i].y()),
                          static_cast<float>(positions[i].z())};
      out.write(reinterpret_cast<const char*>(p), sizeof p);
      out.write(reinterpret_cast<const char*>(colors[i].data()), 3);
    }
    for (const Tri& t : triangles) {
      const unsigned char n = 3;
      out.write(reinterpret_cast<const char*>(&n), 1);
      const std::int32_t idx[3] = {t[0], t[1], t[2]};
      out.write(reinterpret_cast<const char*>(idx), sizeof idx);
    }
    close_written(out, path);
  });
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
