#include "fluidtex/inspect/overlays.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "fluidtex/util/random.h"

namespace fluidtex {

std::array<unsigned char, 3> state_color(DiskState state) {
  switch (state) {
    case DiskState::FadingIn: return {50, 120, 255};
    case DiskState::Active: return {40, 205, 70};
    case DiskState::FadingOutDistorted: return {235, 40, 40};
    case DiskState::FadingOutClose: return {250, 215, 30};
  }
  return {255, 255, 255};
}

double default_depth_bias(const std::vector<Vec3>& positions) {
  return std::max(1e-9, 0.005 * bounding_box(positions).diagonal());
}

void draw_patch_borders(Canvas& canvas, const std::vector<Patch>& patches) {
  for (const Patch& patch : patches) {
    // Edges used by exactly one triangle, in triangle order.
    const std::vector<std::uint8_t> bits = boundary_edge_bits(patch.triangles);
    const LinearRgb color = rgb_from_srgb8(id_color(patch.id));
    for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        if (!(bits[t] & (1u << k))) continue;
        const int a = patch.triangles[t][k], b = patch.triangles[t][(k + 1) % 3];
        canvas.line(patch.positions[std::min(a, b)], patch.positions[std::max(a, b)], color);
      }
    }
  }
}

void draw_disk_states(Canvas& canvas, const std::vector<Patch>& patches, double radius) {
  for (const Patch& patch : patches) {
    canvas.disc(patch.centre.point.position, radius, rgb_from_srgb8(state_color(patch.state)));
  }
}

void draw_velocities(Canvas& canvas, const FrameMesh& mesh, double scale, int spacing) {
  const Camera& camera = canvas.camera;
  spacing = std::max(1, spacing);
  const int cols = (camera.width + spacing - 1) / spacing, rows = (camera.height + spacing - 1) / spacing;
  // Per cell: the visible vertex nearest the cell centre (lowest index on ties).
  std::vector<int> best(static_cast<std::size_t>(cols) * rows, -1);
  std::vector<double> best_d2(best.size(), std::numeric_limits<double>::infinity());
  for (std::size_t v = 0; v < mesh.positions.size() && v < mesh.velocities.size(); ++v) {
    const Vec3& p = mesh.positions[v];
    if (!camera.in_front(p)) continue;
    const Vec3 q = camera.project(p);
    if (!(q.x() >= 0 && q.y() >= 0 && q.x() < camera.width && q.y() < camera.height)) continue;
    const int x = static_cast<int>(q.x()), y = static_cast<int>(q.y());
    if (canvas.depth_test && !canvas.gbuffer.visible(x, y, q.z(), canvas.depth_bias)) continue;
    const int cx = x / spacing, cy = y / spacing;
    const double dx = q.x() - (cx + 0.5) * spacing, dy = q.y() - (cy + 0.5) * spacing;
    const std::size_t cell = static_cast<std::size_t>(cy) * cols + cx;
    const double d2 = dx * dx + dy * dy;
    if (d2 < best_d2[cell]) best_d2[cell] = d2, best[cell] = static_cast<int>(v);
  }
  const LinearRgb white = {1.0f, 1.0f, 1.0f};
  for (int v : best) {
    if (v >= 0) canvas.arrow(mesh.positions[v], mesh.velocities[v] * scale, white);
  }
}

}  // namespace fluidtex
