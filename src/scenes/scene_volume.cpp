// Level-set sampling shared by the 3D scenes (drop, pour).
#include <algorithm>
#include <cmath>

#include <openvdb/openvdb.h>
#include <openvdb/tools/SignedFloodFill.h>

#include "fluidtex/geometry/level_set.h"
#include "scene_volume.h"

namespace fluidtex::detail {

double volume_voxel_size(const SceneOptions& options) { return 2.2 / options.resolution; }

double Pool::distance(const Vec3& p, double top) const {
  // The rounded box: the distance to the box shrunk by `round`, less `round`.
  const Vec3 centre(0.0, 0.0, 0.5 * (top + bottom));
  const Vec3 half(half_width, half_width, 0.5 * (top - bottom));
  const Vec3 q = (p - centre).cwiseAbs() - (half - Vec3::Constant(round));
  const double outside = q.cwiseMax(0.0).norm();
  const double inside = std::min(q.maxCoeff(), 0.0);
  return outside + inside - round;
}

double smooth_union(double a, double b, double k, double* mix) {
  const double h = std::clamp(0.5 + 0.5 * (b - a) / k, 0.0, 1.0);
  if (mix) *mix = h;
  return h * a + (1.0 - h) * b - k * h * (1.0 - h);
}

Vec3 field_gradient(const DistanceField& field, const Vec3& p) {
  const double e = 1e-5;
  Vec3 grad;
  for (int k = 0; k < 3; ++k) {
    Vec3 d = Vec3::Zero();
    d[k] = e;
    grad[k] = (field(p + d) - field(p - d)) / (2.0 * e);
  }
  return grad;
}

FrameMesh mesh_distance_field(const DistanceField& field, const Vec3& lo, const Vec3& hi, double voxel) {
  initialize_openvdb();
  const float half_width = static_cast<float>(3.0 * voxel);
  auto grid = openvdb::FloatGrid::create(half_width);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  const int pad = 5;
  openvdb::Coord imin, imax;
  for (int k = 0; k < 3; ++k) {
    imin[k] = static_cast<int>(std::floor(lo[k] / voxel)) - pad;
    imax[k] = static_cast<int>(std::ceil(hi[k] / voxel)) + pad;
  }
  {
    auto acc = grid->getAccessor();
    for (int i = imin.x(); i <= imax.x(); ++i) {
      for (int j = imin.y(); j <= imax.y(); ++j) {
        for (int k = imin.z(); k <= imax.z(); ++k) {
          const double d = field(Vec3(i * voxel, j * voxel, k * voxel));
          if (std::abs(d) < half_width) acc.setValue(openvdb::Coord(i, j, k), static_cast<float>(d));
        }
      }
    }
  }
  openvdb::tools::signedFloodFill(grid->tree());
  return mesh_level_set(*grid);
}

}  // namespace fluidtex::detail
