// Texel synthesis: Eq. 7's statistics, the single-patch reproduction of the
// exemplar, and raster vs exact agreement.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <string>

#include "fluidtex/scenes/exemplar_gen.h"
#include "fluidtex/scenes/scenes.h"
#include "fluidtex/texture/atlas.h"
#include "fluidtex/texture/synthesis.h"
#include "fluidtex/tracking/tracker.h"
#include "fluidtex/util/random.h"
#include "mesh_fixtures.h"
#include "synthesis_fixtures.h"

namespace fluidtex {
namespace {

/// One flat patch of weight 1 everywhere over a unit square.
TEST(Synthesis, SinglePatchReproducesTheExemplar) {
  test::OnePatch scene(128);
  scene.add(Vec2(0.25, 0.5), 1.0);
  const Exemplar exemplar(make_exemplar("gravel", 64, 3));
  SynthesisOptions so;
  so.tile_size = 1.0;  // the unit square shows exactly one tile
  so.radius = 1e3;     // the fixture's weights: core ≈ w everywhere
  const SynthesisResult r = synthesize(scene.surface, scene.atlas, scene.map, scene.patches, exemplar, so);
  EXPECT_EQ(r.uncovered_texels, 0u);
  ASSERT_GT(r.chart_texels, 5000u);
  // Each texel equals the exemplar's bilinear lookup at its surface point.
  double worst = 0.0;
  for (std::size_t i = 0; i < scene.map.face.size(); ++i) {
    if (scene.map.face[i] < 0) continue;
    const Vec3 q = scene.surface.at(scene.map.face[i], scene.map.bary(i)).position;
    float expect[3];
    exemplar.sample(0.25 + q.x(), 0.5 + q.y(), expect);
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(double(r.color.pixels[i * 3 + c]) - expect[c]));
  }
  EXPECT_LT(worst, 1e-5);
}

/// Two patches of weight 1 over the square whose disks (radius 0.3) sit on
/// opposite corners: each corner blends only its own disk's patch (the other
/// patch's weight there is all coverage tail), the middle, which no disk
/// reaches, blends both tails, and nothing is bare.
TEST(Synthesis, CoverageTailBlendsOnlyWhereNoDiskCovers) {
  test::OnePatch scene(128);
  scene.add(Vec2(0.25, 0.5), 1.0);
  for (Vec2& uv : scene.add(Vec2(0.6, 0.1), 1.0).uvs) uv -= Vec2(1.0, 1.0);  // disk centre at (1, 1)
  const Exemplar exemplar(make_exemplar("gravel", 64, 3));
  SynthesisOptions so;
  so.tile_size = 1.0;
  so.radius = 0.3;
  so.aov = true;
  const SynthesisResult r = synthesize(scene.surface, scene.atlas, scene.map, scene.patches, exemplar, so);
  EXPECT_EQ(r.uncovered_texels, 0u);
  std::size_t corner = 0, middle = 0;
  double worst = 0.0;
  for (std::size_t i = 0; i < scene.map.face.size(); ++i) {
    if (scene.map.face[i] < 0) continue;
    // Each patch once, also where a core and the tails blend together.
    EXPECT_LE(r.count.pixels[i], 2.0f) << i;
    const Vec3 q = scene.surface.at(scene.map.face[i], scene.map.bary(i)).position;
    const double da = Vec2(q.x(), q.y()).norm(), db = Vec2(q.x() - 1.0, q.y() - 1.0).norm();
    if (da < 0.25 || db < 0.25) {
      ++corner;
      EXPECT_EQ(r.count.pixels[i], 1.0f);
      float expect[3];
      if (da < 0.25)
        exemplar.sample(0.25 + q.x(), 0.5 + q.y(), expect);
      else
        exemplar.sample(0.6 + q.x() - 1.0, 0.1 + q.y() - 1.0, expect);
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(double(r.color.pixels[i * 3 + c]) - expect[c]));
    } else if (da > 0.3 + 0.18 && db > 0.3 + 0.18) {  // vertex weights interpolate over 0.125-cells (diagonal < 0.18)
      ++middle;
      EXPECT_EQ(r.count.pixels[i], 2.0f);
    }
  }
  EXPECT_GT(corner, 300u);
  EXPECT_GT(middle, 300u);
  EXPECT_LT(worst, 1e-5);
}

/// Two patches over the whole square, one at K_t = 1 and one fading in at
/// K_t = 0.2: with --weight-cutoff t each blends max(0, core − t·max core),
/// so the weak one drops out once t ≥ 0.2 and is scaled down before that.
TEST(Synthesis, WeightCutoffDropsWeakPatchesContinuously) {
  test::OnePatch scene(128);
  scene.add(Vec2(0.25, 0.5), 1.0);
  Patch& weak = scene.add(Vec2(0.7, 0.15), 0.2, 0.8);
  weak.kt = 0.2;
  const Exemplar exemplar(make_exemplar("gravel", 64, 3));
  SynthesisOptions so;
  so.tile_size = 1.0;
  so.radius = 1e3;  // core ≈ K_t everywhere, the same radial factor for both
  so.aov = true;
  for (const double t : {0.0, 0.1, 0.19, 0.21, 0.5}) {  // not 0.2 itself: K_t is a float
    SCOPED_TRACE(t);
    so.weight_cutoff = t;
    const SynthesisResult r = synthesize(scene.surface, scene.atlas, scene.map, scene.patches, exemplar, so);
    EXPECT_EQ(r.uncovered_texels, 0u);
    const double wa = 1.0 - t, wb = std::max(0.0, 0.2 - t);
    double worst = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < scene.map.face.size(); ++i) {
      if (scene.map.face[i] < 0) continue;
      ++n;
      EXPECT_EQ(r.count.pixels[i], wb > 0.0 ? 2.0f : 1.0f);
      const Vec3 q = scene.surface.at(scene.map.face[i], scene.map.bary(i)).position;
      const double cb = std::cos(0.8), sb = std::sin(0.8);
      float a[3], b[3];
      exemplar.sample(0.25 + q.x(), 0.5 + q.y(), a);
      exemplar.sample(0.7 + cb * q.x() - sb * q.y(), 0.15 + sb * q.x() + cb * q.y(), b);
      for (int c = 0; c < 3; ++c) {
        const double m = exemplar.mean()[c];
        const double expect =
            std::clamp((wa * (a[c] - m) + wb * (b[c] - m)) / std::sqrt(wa * wa + wb * wb) + m, 0.0, 1.0);  // Eq. 7
        worst = std::max(worst, std::abs(double(r.color.pixels[i * 3 + c]) - expect));
      }
    }
    ASSERT_GT(n, 5000u);
    EXPECT_LT(worst, 2e-3);  // the radial factor 1 − |uv|/1e3 differs between the two only through rounding
  }
}

/// Two patches over the square whose weights are 0 everywhere (both all
/// margin): no texel is left bare; each shows, as a last resort, the patch
/// whose centre is nearer in uv, and is counted as a margin texel.
TEST(Synthesis, MarginIsTheLastResort) {
  test::OnePatch scene(128);
  scene.add(Vec2(0.25, 0.5), 0.0);
  for (Vec2& uv : scene.add(Vec2(0.6, 0.1), 0.0).uvs) uv -= Vec2(1.0, 1.0);  // centre at (1, 1)
  const Exemplar exemplar(make_exemplar("gravel", 64, 3));
  SynthesisOptions so;
  so.tile_size = 1.0;
  so.radius = 0.3;
  so.projection_tolerance = 0.05;
  for (const SynthesisScheme scheme : {SynthesisScheme::Raster, SynthesisScheme::Exact}) {
    SCOPED_TRACE(scheme == SynthesisScheme::Raster ? "raster" : "exact");
    so.scheme = scheme;
    const SynthesisResult r = synthesize(scene.surface, scene.atlas, scene.map, scene.patches, exemplar, so);
    ASSERT_GT(r.chart_texels, 5000u);
    EXPECT_EQ(r.uncovered_texels, 0u);
    EXPECT_EQ(r.margin_texels, r.chart_texels);
    double worst = 0.0;
    for (std::size_t i = 0; i < scene.map.face.size(); ++i) {
      if (scene.map.face[i] < 0) continue;
      const Vec3 q = scene.surface.at(scene.map.face[i], scene.map.bary(i)).position;
      const double da = Vec2(q.x(), q.y()).norm(), db = Vec2(q.x() - 1.0, q.y() - 1.0).norm();
      if (std::abs(da - db) < 0.02) continue;  // the two sides of the bisector, within a texel
      float expect[3];
      if (da < db)
        exemplar.sample(0.25 + q.x(), 0.5 + q.y(), expect);
      else
        exemplar.sample(0.6 + q.x() - 1.0, 0.1 + q.y() - 1.0, expect);
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(double(r.color.pixels[i * 3 + c]) - expect[c]));
    }
    EXPECT_LT(worst, 1e-5);
  }
}

/// A face the atlas puts in a chart of its own (here: its corners are not
/// shared with the faces around it) under one patch that spans it: the
/// patch's triangles over it have their corners in the surrounding chart and
/// are rasterised there, yet the face's own texels, elsewhere in the atlas,
/// get the patch too, as the exact method gives them (without the raster's
/// last pass over unreached texels: about 240 bare texels).
TEST(Synthesis, RasterCoversAFaceInAChartOfItsOwn) {
  FrameMesh mesh = test::flat_grid(8);
  const int sliver = 1;  // on the square's edge: the rest stays a disk, one chart around it
  const Tri cut = mesh.triangles[sliver];
  for (int k = 0; k < 3; ++k) {
    mesh.triangles[sliver][k] = static_cast<int>(mesh.positions.size());
    mesh.positions.push_back(mesh.positions[cut[k]]);
    mesh.velocities.push_back(mesh.velocities[cut[k]]);
  }
  const SurfaceIndex surface(mesh);
  AtlasOptions ao;
  ao.size = 256;
  ao.min_fill = 0.0;  // the faces around it in one chart
  const Atlas atlas = build_atlas(surface, ao);
  const int own = atlas.face_chart[sliver];
  ASSERT_EQ(atlas.charts[own].faces, std::vector<int>{sliver});
  std::set<int> around;  // the charts of the faces that touch it
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      for (int v : cut) {
        if (f != static_cast<std::size_t>(sliver) && mesh.triangles[f][k] == v) around.insert(atlas.face_chart[f]);
      }
    }
  }
  ASSERT_EQ(around.size(), 1u);
  const TexelMap map = build_texel_map(surface, atlas);
  test::OnePatch scene(256);  // the patch: the unsplit grid
  Patch& patch = scene.add(Vec2(0.25, 0.5), 1.0);
  // Every patch vertex lies on a face of the surrounding chart (as on a real
  // mesh, where the sliver's corners are shared with the faces around it):
  // no patch triangle has a corner in the face's own chart.
  for (std::size_t v = 0; v < patch.positions.size(); ++v) {
    SurfacePoint& s = patch.projections[v];
    if (s.face != sliver) continue;
    for (std::size_t f = 0; f < scene.mesh.triangles.size() && s.face == sliver; ++f) {
      const Tri& t = scene.mesh.triangles[f];
      for (int k = 0; k < 3; ++k) {
        if (f == static_cast<std::size_t>(sliver) || t[k] != static_cast<int>(v)) continue;
        s.face = static_cast<int>(f);
        s.bary = Vec3::Zero();
        s.bary[k] = 1.0;
      }
    }
    ASSERT_NE(s.face, sliver);
  }
  const Exemplar exemplar(make_exemplar("gravel", 64, 3));
  SynthesisOptions so;
  so.tile_size = 1.0;
  so.radius = 1e3;
  so.projection_tolerance = 0.05;
  const SynthesisResult raster = synthesize(surface, atlas, map, scene.patches, exemplar, so);
  so.scheme = SynthesisScheme::Exact;
  const SynthesisResult exact = synthesize(surface, atlas, map, scene.patches, exemplar, so);
  EXPECT_EQ(exact.uncovered_texels, 0u);
  EXPECT_EQ(raster.uncovered_texels, 0u);
  std::size_t inside = 0;
  double worst = 0.0;
  for (std::size_t i = 0; i < map.face.size(); ++i) {
    if (map.face[i] != sliver) continue;
    ++inside;
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(double(raster.color.pixels[i * 3 + c]) - exact.color.pixels[i * 3 + c]));
  }
  EXPECT_GT(inside, 100u);
  EXPECT_LT(worst, 1e-5);
}

TEST(Synthesis, Eq7KeepsMeanAndVarianceOfUncorrelatedPatches) {
  // Four patches with equal weight, far-apart anchors and turned uv: their
  // lookups are uncorrelated. Eq. 7 keeps the exemplar's mean and variance;
  // linear blending keeps the mean and loses contrast (≈ 1/sqrt(4)).
  test::OnePatch scene(256);
  for (int k = 0; k < 4; ++k) scene.add(Vec2(0.13 * k + 0.05, 0.29 * k + 0.1), 1.0, 0.9 * k);
  const Exemplar exemplar(make_exemplar("gravel", 64, 11));
  SynthesisOptions so;
  so.tile_size = 0.25;  // 16 tiles over the square: good statistics
  so.radius = 1e3;
  auto stats = [&](Blend blend) {
    so.blend = blend;
    const SynthesisResult r = synthesize(scene.surface, scene.atlas, scene.map, scene.patches, exemplar, so);
    double sum = 0, sum2 = 0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < scene.map.face.size(); ++i) {
      if (scene.map.face[i] < 0) continue;
      const double v = r.color.pixels[i * 3 + 1];
      sum += v, sum2 += v * v, ++n;
    }
    const double mean = sum / n;
    return std::make_pair(mean, std::sqrt(sum2 / n - mean * mean));
  };
  const auto [mean7, sd7] = stats(Blend::ContrastPreserving);
  const auto [mean_lin, sd_lin] = stats(Blend::Linear);
  EXPECT_NEAR(mean7, exemplar.mean()[1], 0.03);
  EXPECT_NEAR(sd7 / exemplar.stddev()[1], 1.0, 0.15);
  EXPECT_NEAR(mean_lin, exemplar.mean()[1], 0.03);
  EXPECT_LT(sd_lin / exemplar.stddev()[1], 0.75);
}

TEST(Synthesis, RasterAgreesWithExactAndCoversGeneratedScenes) {
  SceneOptions so;
  so.resolution = 24;
  so.frames = 48;
  const Exemplar exemplar(make_exemplar("bubbles", 64, 5));
  for (const char* scene : {"rotation", "merge", "drop"}) {
    SCOPED_TRACE(scene);
    TrackerSettings ts;
    ts.seed = 3;
    Tracker tracker(ts);
    for (int f = 1; f <= 6; ++f) {
      tracker.step(std::make_shared<FrameMesh>(make_scene_frame(scene, f, so)), f, 1.0 / so.fps);
    }
    AtlasOptions ao;
    ao.size = 256;
    const Atlas atlas = build_atlas(*tracker.surface(), ao);
    const TexelMap map = build_texel_map(*tracker.surface(), atlas);
    SynthesisOptions opt;
    const TrackingOptions& o = tracker.settings().tracking;
    opt.tile_size = o.exemplar_tile_size();
    opt.radius = o.d();
    opt.projection_tolerance = o.mpt();
    const SynthesisResult raster = synthesize(*tracker.surface(), atlas, map, tracker.patches(), exemplar, opt);
    opt.scheme = SynthesisScheme::Exact;
    const SynthesisResult exact = synthesize(*tracker.surface(), atlas, map, tracker.patches(), exemplar, opt);
    if (std::string(scene) == "merge") {
      // The merge outline grows faster than patches follow near the neck;
      // the tracker refills such gaps from its candidates one frame later,
      // and a texel or two between candidates can stay bare (measured: 1 of
      // ~25k here). Known gap, reported in stats as uncovered_fraction.
      EXPECT_LE(raster.uncovered_fraction(), 1e-3);
      EXPECT_LE(exact.uncovered_fraction(), 1e-3);
    } else {
      EXPECT_EQ(raster.uncovered_texels, 0u);
      EXPECT_EQ(exact.uncovered_texels, 0u);
    }
    // Away from chart borders they agree closely.
    std::size_t n = 0, far = 0;
    double mean_diff = 0.0;
    const int size = atlas.size;
    for (std::size_t i = 0; i < map.face.size(); ++i) {
      if (map.face[i] < 0) continue;
      const int x = static_cast<int>(i % size), y = static_cast<int>(i / size);
      bool interior = true;
      for (int dy = -2; dy <= 2 && interior; ++dy) {
        for (int dx = -2; dx <= 2 && interior; ++dx) {
          const int xx = x + dx, yy = y + dy;
          interior =
              xx >= 0 && yy >= 0 && xx < size && yy < size && map.face[static_cast<std::size_t>(yy) * size + xx] >= 0 &&
              atlas.face_chart[map.face[static_cast<std::size_t>(yy) * size + xx]] == atlas.face_chart[map.face[i]];
        }
      }
      if (!interior) continue;
      for (int c = 0; c < 3; ++c) {
        const double d = std::abs(raster.color.pixels[i * 3 + c] - exact.color.pixels[i * 3 + c]);
        mean_diff += d;
        far += d > 0.05;
        ++n;
      }
    }
    ASSERT_GT(n, 1000u);
    EXPECT_LT(mean_diff / n, 0.002);
    EXPECT_LT(static_cast<double>(far) / n, 0.01);
  }
}

TEST(Dilation, FillsGuttersFromTheCharts) {
  Image im;
  im.width = im.height = 8;
  im.channels = 1;
  im.pixels.assign(64, 0.0f);
  std::vector<char> mask(64, 0);
  im.pixels[3 * 8 + 3] = 1.0f;
  mask[3 * 8 + 3] = 1;
  dilate(im, mask, 2);
  EXPECT_EQ(im.pixels[3 * 8 + 5], 1.0f);  // two rings out
  EXPECT_EQ(im.pixels[3 * 8 + 6], 0.0f);  // three rings out: untouched
  EXPECT_EQ(mask[3 * 8 + 5], 1);
  EXPECT_EQ(mask[3 * 8 + 6], 0);
}

TEST(Dilation, EachRingAveragesTheFilledNeighboursAsTheRingStarts) {
  // A random mask over an odd-sized image (edges and corners included),
  // against the rule spelled out: every ring, each empty texel with a
  // filled 8-neighbour takes the mean of those neighbours.
  const int w = 37, h = 23, rings = 3;
  Image im;
  im.width = w, im.height = h, im.channels = 2;
  im.pixels.assign(static_cast<std::size_t>(w) * h * 2, 0.0f);
  std::vector<char> mask(static_cast<std::size_t>(w) * h, 0);
  for (std::size_t i = 0; i < mask.size(); ++i) {
    mask[i] = to_unit(hash_values({7, i})) < 0.08;
    if (mask[i]) im.pixels[2 * i] = static_cast<float>(i), im.pixels[2 * i + 1] = 1.0f;
  }
  Image want = im;
  std::vector<char> want_mask = mask;
  for (int ring = 0; ring < rings; ++ring) {
    const Image before = want;
    const std::vector<char> filled = want_mask;
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        if (filled[texel_index(x, y, w)]) continue;
        float acc[2] = {0, 0};
        int n = 0;
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if (xx < 0 || yy < 0 || xx >= w || yy >= h || !filled[texel_index(xx, yy, w)]) continue;
            for (int c = 0; c < 2; ++c) acc[c] += before.pixel(texel_index(xx, yy, w))[c];
            ++n;
          }
        }
        if (n == 0) continue;
        for (int c = 0; c < 2; ++c) want.pixel(texel_index(x, y, w))[c] = acc[c] / static_cast<float>(n);
        want_mask[texel_index(x, y, w)] = 1;
      }
    }
  }
  dilate(im, mask, rings);
  EXPECT_EQ(mask, want_mask);
  EXPECT_EQ(im.pixels, want.pixels);
}

}  // namespace
}  // namespace fluidtex
