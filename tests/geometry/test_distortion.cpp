// Sorkine distortion (geometry/distortion.h) on known affine maps.
#include <gtest/gtest.h>

#include "fluidtex/geometry/distortion.h"

namespace fluidtex {
namespace {

// --- Distortion (Sorkine) --------------------------------------------------

TEST(Distortion, KnownAffineMaps) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0.3, 0.8, 0);
  const RestTriangle rest = rest_shape(a, b, c);
  EXPECT_NEAR(triangle_distortion(rest, a, b, c), 1.0, 1e-12);
  // A rigid motion in 3D is still an isometry.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  EXPECT_NEAR(triangle_distortion(rest, R * a + Vec3(5, 1, 2), R * b + Vec3(5, 1, 2), R * c + Vec3(5, 1, 2)), 1.0,
              1e-12);
  const Eigen::Matrix3d stretch = Vec3(2, 1, 1).asDiagonal();
  EXPECT_NEAR(triangle_distortion(rest, stretch * a, stretch * b, stretch * c), 2.0, 1e-12);
  const Eigen::Matrix3d shrink = Vec3(1, 0.5, 1).asDiagonal();
  EXPECT_NEAR(triangle_distortion(rest, shrink * a, shrink * b, shrink * c), 2.0, 1e-12);
  EXPECT_TRUE(std::isinf(triangle_distortion(rest, a, b, a)));  // collapsed
  EXPECT_DOUBLE_EQ(triangle_quality(1.0, 3.0), 1.0);
  EXPECT_DOUBLE_EQ(triangle_quality(2.0, 3.0), 0.5);
  EXPECT_DOUBLE_EQ(triangle_quality(4.0, 3.0), 0.0);
}

}  // namespace
}  // namespace fluidtex
