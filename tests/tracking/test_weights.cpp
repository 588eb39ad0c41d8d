// The vertex weights of a patch (tracking/weights.h): Eq. 4 and 2 with the
// coverage tail.
#include <gtest/gtest.h>

#include "fluidtex/tracking/patch.h"
#include "fluidtex/tracking/weights.h"

namespace fluidtex {
namespace {

TEST(Weights, Eq4SpatialTimesTemporal) {
  Patch p;
  p.positions.assign(4, Vec3::Zero());
  p.uvs = {Vec2(0, 0), Vec2(0.05, 0), Vec2(0.0, 0.2), Vec2(0.03, 0.04)};
  p.border = {0, 0, 0, 1};
  p.quality = {1.0f, 0.5f, 1.0f, 1.0f};
  p.kt = 0.5;
  TrackingOptions o;
  o.radius = 0.1;
  o.uv_scale = 1.0;
  o.selection_margin = 0.6;
  update_weights(p, o);
  // Eq. 4 plus the coverage tail ε·(1 − r/((1 + β)d)), (1 + β)d = 0.16.
  const double eps = kCoverageTail;
  EXPECT_NEAR(p.weight[0], (1 + eps) * 0.5, 1e-7);                                    // centre: K_S = 1
  EXPECT_NEAR(p.weight[1], ((1 - 0.5) + eps * (1 - 0.05 / 0.16)) * 0.5 * 0.5, 1e-7);  // half way, Q_V = 0.5
  EXPECT_EQ(p.weight[2], 0.0f);                                                       // beyond (1 + β)d
  // Border: d_V = 0 takes the disk's term; the tail stays, so that a patch
  // the plane test cut short still covers its own surface.
  EXPECT_NEAR(p.weight[3], eps * (1 - 0.05 / 0.16) * 0.5, 1e-7);
  EXPECT_EQ(core_weight(p, 3, o.radius.value(), o.uv_scale), 0.0f);  // Eq. 4 alone
}

}  // namespace
}  // namespace fluidtex
