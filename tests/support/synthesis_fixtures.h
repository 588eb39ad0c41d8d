// A flat unit square (8×8 grid), its atlas and texel map, and patches that
// cover it whole with a constant weight: synthesis cases with known answers.
#pragma once

#include <cmath>
#include <vector>

#include "fluidtex/geometry/surface.h"
#include "fluidtex/texture/atlas.h"
#include "fluidtex/texture/synthesis.h"
#include "fluidtex/tracking/patch.h"
#include "mesh_fixtures.h"

namespace fluidtex::test {

struct OnePatch {
  FrameMesh mesh = flat_grid(8);
  SurfaceIndex surface{mesh};
  Atlas atlas;
  TexelMap map;
  std::vector<Patch> patches;

  explicit OnePatch(int size) {
    AtlasOptions o;
    o.size = size;
    atlas = build_atlas(surface, o);
    map = build_texel_map(surface, atlas);
  }
  Patch& add(const Vec2& anchor, double weight, double rotate = 0.0) {
    Patch p;
    p.id = static_cast<std::uint32_t>(patches.size());
    p.kt = 1.0;
    p.anchor = anchor;
    p.positions = mesh.positions;
    p.triangles = mesh.triangles;
    const double c = std::cos(rotate), s = std::sin(rotate);
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      const Vec3& q = mesh.positions[v];
      p.uvs.emplace_back(c * q.x() - s * q.y(), s * q.x() + c * q.y());
      p.projections.push_back(surface.closest_point(q));
    }
    p.weight.assign(mesh.positions.size(), static_cast<float>(weight));
    p.border.assign(mesh.positions.size(), 0);
    p.quality.assign(mesh.positions.size(), 1.0f);
    patches.push_back(std::move(p));
    return patches.back();
  }
};

}  // namespace fluidtex::test
