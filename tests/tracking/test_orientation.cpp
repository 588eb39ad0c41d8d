// Patch orientation (tracking/orientation.h): the chart maps, the world-axis
// field of a first frame, births that agree with the patches around them,
// flow-aligned patches, and what synthesis shows: a directional exemplar
// keeps its direction on the surface.
#include <gtest/gtest.h>

#include <cmath>

#include "fluidtex/geometry/surface.h"
#include "fluidtex/texture/atlas.h"
#include "fluidtex/texture/exemplar.h"
#include "fluidtex/texture/synthesis.h"
#include "fluidtex/tracking/orientation.h"
#include "fluidtex/tracking/tracker.h"
#include "mesh_fixtures.h"

namespace fluidtex {
namespace {

constexpr double kDegree = M_PI / 180.0;

/// A patch's u axis in 3D: ∂x/∂u over its disk triangles, weighted by area.
Vec3 patch_u_axis(const Patch& p, double d) {
  Vec3 sum = Vec3::Zero();
  for (const Tri& t : p.triangles) {
    const Vec2 c = (p.uvs[t[0]] + p.uvs[t[1]] + p.uvs[t[2]]) / 3.0;
    if (c.norm() < d) sum += triangle_area(p.positions, t) * u_axis(p, t).normalized();
  }
  return sum.normalized();
}

/// The angle between two unit vectors, in degrees.
double degrees_between(const Vec3& a, const Vec3& b) { return std::acos(std::clamp(a.dot(b), -1.0, 1.0)) / kDegree; }

std::shared_ptr<FrameMesh> plane(const std::function<Vec3(const Vec3&)>& velocity = nullptr) {
  return std::make_shared<FrameMesh>(test::flat_grid(40, 1.0, 0.0, -0.5, -0.5, velocity));
}

TrackerSettings settings(Orientation orientation) {
  TrackerSettings s;
  s.tracking.radius = 0.12;
  s.tracking.fade_frames = 8;
  s.tracking.orientation = orientation;
  s.seed = 5;
  return s;
}

TEST(Orientation, ChartMapsInvertEachOther) {
  Patch p;
  p.positions = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0)};
  p.uvs = {Vec2(0, 0), Vec2(0, 1), Vec2(-0.5, 0)};  // u runs along −y at half scale
  const Tri t{0, 1, 2};
  EXPECT_NEAR((u_axis(p, t) - Vec3(0, -2, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((uv_of(p, t, Vec3(0, -2, 0)) - Vec2(1, 0)).norm(), 0.0, 1e-12);
  // The normal part of a vector is dropped.
  EXPECT_NEAR((uv_of(p, t, Vec3(2, 0, 5)) - Vec2(0, 1)).norm(), 0.0, 1e-12);
  // Turning the uv by +90° brings the direction at −90° in uv (−v, which
  // runs along −x) onto u.
  turn_uv(p, 90 * kDegree);
  EXPECT_NEAR((u_axis(p, t).normalized() - Vec3(-1, 0, 0)).norm(), 0.0, 1e-12);
}

TEST(Orientation, WorldAxisTakesTheNextWhereTheSurfaceFacesIt) {
  EXPECT_NEAR((world_direction(Axis::X, Vec3(0, 0, 1)) - Vec3(1, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((world_direction(Axis::X, Vec3(1, 0, 0)) - Vec3(0, 1, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((world_direction(Axis::Z, Vec3(0, 0, 1)) - Vec3(1, 0, 0)).norm(), 0.0, 1e-12);
  const Vec3 tilted = world_direction(Axis::X, Vec3(1, 0, 1).normalized());
  EXPECT_NEAR((tilted - Vec3(1, 0, -1).normalized()).norm(), 0.0, 1e-12);
}

TEST(Orientation, FirstFramePatchesFollowTheWorldAxis) {
  for (Axis axis : {Axis::X, Axis::Y}) {
    TrackerSettings s = settings(Orientation::Field);
    s.tracking.orientation_axis = axis;
    Tracker t(s);
    t.step(plane(), 1, 1.0 / 24);
    ASSERT_GT(t.patches().size(), 10u);
    for (const Patch& p : t.patches())
      EXPECT_LT(degrees_between(patch_u_axis(p, 0.12), Vec3::Unit(static_cast<int>(axis))), 1.0) << p.id;
  }
  // As LSCM leaves them, the charts point every which way.
  Tracker random(settings(Orientation::Random));
  random.step(plane(), 1, 1.0 / 24);
  double widest = 0.0;
  for (const Patch& p : random.patches())
    widest = std::max(widest, degrees_between(patch_u_axis(p, 0.12), Vec3::UnitX()));
  EXPECT_GT(widest, 30.0);
}

/// The largest angle, over the patches born after frame 1, between a
/// birth's u axis at its centre and that of the older patches over it.
double worst_birth_disagreement(Orientation orientation) {
  const double omega = 1.5;  // a rigid rotation: the older patches all turn alike
  Tracker t(settings(orientation));
  int births = 0;
  double worst = 0.0;
  for (int f = 1; f <= 24; ++f) {
    t.step(plane([&](const Vec3& q) { return Vec3(-omega * q.y(), omega * q.x(), 0); }), f, 1.0 / 24);
    // On a rigid rotation every older patch has turned by ω·t since it was
    // born along x; so has its u axis.
    const double turned = omega * (f - 1) / 24.0;
    const Vec3 field(std::cos(turned), std::sin(turned), 0.0);
    for (const Patch& p : t.patches()) {
      if (p.created_frame != f || f == 1 || p.recut_frame >= 0) continue;
      ++births;
      worst = std::max(worst, degrees_between(patch_u_axis(p, 0.12), field));
    }
  }
  EXPECT_GT(births, 3);
  return worst;
}

TEST(Orientation, BirthsAgreeWithThePatchesAroundThem) {
  EXPECT_LT(worst_birth_disagreement(Orientation::Field), 3.0);
  EXPECT_GT(worst_birth_disagreement(Orientation::Random), 30.0);
}

TEST(Orientation, FlowFollowsAFastSurface) {
  const Vec3 v = Vec3(1, 2, 0).normalized() * 0.5;  // 0.02 per frame: 0.17 d
  TrackerSettings s = settings(Orientation::Flow);
  s.tracking.gap_fill = GapFill::Seed;
  Tracker t(s);
  t.step(plane([&](const Vec3&) { return v; }), 1, 1.0 / 24);
  for (const Patch& p : t.patches()) EXPECT_LT(degrees_between(patch_u_axis(p, 0.12), v.normalized()), 1.0);
  // Slow, it takes the field.
  Tracker slow(s);
  slow.step(plane([&](const Vec3&) { return 0.01 * v; }), 1, 1.0 / 24);
  for (const Patch& p : slow.patches()) EXPECT_LT(degrees_between(patch_u_axis(p, 0.12), Vec3::UnitX()), 1.0);
}

TEST(Orientation, AnchorDistanceWrapsAroundTheTile) {
  EXPECT_NEAR(anchor_distance(Vec2(0.05, 0.5), Vec2(0.95, 0.5)), 0.1, 1e-12);
  EXPECT_NEAR(anchor_distance(Vec2(0.1, 0.1), Vec2(0.4, 0.5)), 0.5, 1e-12);
  EXPECT_NEAR(anchor_distance(Vec2(0.0, 0.0), Vec2(0.5, 0.5)), std::sqrt(0.5), 1e-12);
}

/// The share of neighbouring pairs (centres within kNeighbourSpan·d) whose
/// anchors lie closer than kAnchorSeparation, after frame 1 of a plane.
double close_anchor_share(Orientation orientation) {
  Tracker t(settings(orientation));
  t.step(plane(), 1, 1.0 / 24);
  const std::vector<Patch>& p = t.patches();
  int pairs = 0, close = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      if ((p[i].centre.point.position - p[j].centre.point.position).norm() >= kNeighbourSpan * 0.12) continue;
      ++pairs;
      close += anchor_distance(p[i].anchor, p[j].anchor) < kAnchorSeparation;
    }
  }
  EXPECT_GT(pairs, 50);
  return static_cast<double>(close) / pairs;
}

TEST(Orientation, NeighboursShowDifferentPartsOfTheExemplar) {
  EXPECT_LT(close_anchor_share(Orientation::Field), 0.02);
  EXPECT_GT(close_anchor_share(Orientation::Random), 0.08);  // π·0.25² of pairs drawn at random
}

// --- What synthesis shows ------------------------------------------------------

/// Tileable stripes, 64², wave vector (4, 2) cycles per tile in (u, v).
Exemplar stripes() {
  Image image = Image::blank(64, 64, 1);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      const double v = 63 - y + 0.5, u = x + 0.5;  // image rows run down, v up
      image.at(x, y, 0) = static_cast<float>(0.5 + 0.4 * std::sin(2.0 * M_PI * (4 * u + 2 * v) / 64.0));
    }
  }
  return Exemplar(std::move(image));
}

/// Dominant gradient direction (radians, mod π) and coherence of a square
/// grid of samples f(i, j) spaced one unit apart (i along the first axis).
std::pair<double, double> structure(const std::function<double(int, int)>& f, int n) {
  double xx = 0.0, xy = 0.0, yy = 0.0;
  for (int j = 1; j + 1 < n; ++j) {
    for (int i = 1; i + 1 < n; ++i) {
      const double gx = 0.5 * (f(i + 1, j) - f(i - 1, j)), gy = 0.5 * (f(i, j + 1) - f(i, j - 1));
      xx += gx * gx, xy += gx * gy, yy += gy * gy;
    }
  }
  const double angle = 0.5 * std::atan2(2.0 * xy, xx - yy);
  const double coherence = std::sqrt((xx - yy) * (xx - yy) + 4.0 * xy * xy) / (xx + yy);
  return {angle, coherence};
}

/// The structure of the atlas synthesised from frame 1 of a plane, read
/// back on the plane (x, y) through the atlas, against the exemplar's in (u, v).
void expect_exemplar_direction(Orientation orientation, bool oriented) {
  const TrackerSettings s = settings(orientation);
  Tracker t(s);
  t.step(plane(), 1, 1.0 / 24);
  const SurfaceIndex& surface = *t.surface();
  AtlasOptions ao;
  ao.size = 512;
  const Atlas atlas = build_atlas(surface, ao);
  const TexelMap map = build_texel_map(surface, atlas);
  const Exemplar exemplar = stripes();
  SynthesisOptions so;
  so.radius = 0.12, so.tile_size = 0.3, so.projection_tolerance = t.settings().tracking.mpt();
  const SynthesisResult r = synthesize(surface, atlas, map, t.patches(), exemplar, so);
  // 0.6 × 0.6 of the plane's middle, at 200 samples (4.7 per stripe period).
  const int n = 200;
  const auto on_plane = [&](int i, int j) {
    const SurfacePoint q = surface.closest_point(Vec3(-0.3 + 0.6 * i / n, -0.3 + 0.6 * j / n, 0.0));
    const auto& c = atlas.corner_px[q.face];
    const Vec2 px = interpolate(q.bary, c[0], c[1], c[2]);
    return static_cast<double>(
        r.color.at(std::clamp(static_cast<int>(px.x()), 0, 511), std::clamp(static_cast<int>(px.y()), 0, 511), 0));
  };
  const auto in_exemplar = [&](int i, int j) {
    float value;
    exemplar.sample(2.0 * i / n, 2.0 * j / n, &value);  // the same 0.6 / 0.3 tiles
    return static_cast<double>(value);
  };
  const auto [angle, coherence] = structure(on_plane, n);
  const auto [expected_angle, expected_coherence] = structure(in_exemplar, n);
  const double off = std::abs(std::remainder(angle - expected_angle, M_PI)) / kDegree;
  if (oriented) {
    EXPECT_LT(off, 10.0);
    EXPECT_GT(coherence, 0.7 * expected_coherence);
  } else {
    EXPECT_TRUE(off > 10.0 || coherence < 0.7 * expected_coherence) << off << " " << coherence;
  }
}

TEST(Orientation, SynthesisKeepsTheExemplarsDirection) {
  expect_exemplar_direction(Orientation::Field, true);
  expect_exemplar_direction(Orientation::Random, false);
}

}  // namespace
}  // namespace fluidtex
