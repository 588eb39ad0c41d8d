// The flow-map baseline (two-phase advected UVs): transport of the uv sets,
// the phase weights, a whole run through the command line, and bad options.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "fluidtex/job/pipeline.h"
#include "fluidtex/scenes/exemplar_gen.h"
#include "fluidtex/scenes/scenes.h"
#include "fluidtex/texture/atlas.h"
#include "fluidtex/texture/flowmap.h"
#include "fluidtex/util/error.h"
#include "mesh_fixtures.h"
#include "test_util.h"

namespace fluidtex {
namespace {

namespace fs = std::filesystem;
using test::run_fluidtex;

std::string q(const std::string& s) { return "'" + s + "'"; }

/// radius 0: automatic.
FlowMapSettings settings(int period, double radius) {
  FlowMapSettings s;
  s.flowmap.period = period;
  if (radius > 0.0) s.tracking.radius = radius;
  s.tracking.selection_margin = 0.6;
  return s;
}

TEST(FlowMap, UniformFlowMovesTheTextureWithIt) {
  // A static square domain [-1,1]² with a uniform velocity, remeshed every
  // frame (alternating grid resolutions: no vertex survives from one frame to
  // the next). No reset within the window: uv(x, t) = rest(x) − v·t / T.
  const Vec3 v(0.3, 0.1, 0.0);
  const double dt = 1.0 / 24.0;
  FlowMapAdvector advector(settings(64, 0.1));
  const double tile = (2.0 + 0.6) * 0.1;
  const int steps = 5;
  for (int k = 0; k < steps; ++k) {
    const int n = k % 2 == 0 ? 20 : 23;
    auto mesh =
        std::make_shared<const FrameMesh>(test::flat_grid(n, 2.0, 0.0, -1.0, -1.0, [&](const Vec3&) { return v; }));
    const FlowMapStep step = advector.step(mesh, dt);
    EXPECT_EQ(step.step, k);
    EXPECT_EQ(step.reset[0], k == 0);
    EXPECT_EQ(step.reset[1], k == 0);
    EXPECT_NEAR(advector.tile_size(), tile, 1e-15);
    const double t = k * dt;
    // Every vertex, the inflow rim included (traced back beyond the rim, the
    // field is extended with the rest gradient).
    int checked = 0;
    for (std::size_t i = 0; i < mesh->num_vertices(); ++i) {
      const Vec3& x = mesh->positions[i];
      const Vec2 expected = rest_uv(x, Axis::Z, tile) - Vec2(v.x(), v.y()) * t / tile;
      for (int phase = 0; phase < 2; ++phase) {
        ASSERT_NEAR(advector.uv(phase)[i].x(), expected.x(), 1e-9) << "step " << k << " vertex " << i;
        ASSERT_NEAR(advector.uv(phase)[i].y(), expected.y(), 1e-9) << "step " << k << " vertex " << i;
      }
      ++checked;
    }
    EXPECT_EQ(checked, static_cast<int>(mesh->num_vertices())) << "step " << k;
  }
}

TEST(FlowMap, ResetsReturnToRestOnTheirPhase) {
  // Period 4: A resets at steps 0, 4, 8; B at 2, 6. A reset phase is at rest;
  // the other one keeps moving.
  const Vec3 v(0.5, 0.0, 0.0);
  FlowMapAdvector advector(settings(4, 0.1));
  for (int k = 0; k < 9; ++k) {
    auto mesh =
        std::make_shared<const FrameMesh>(test::flat_grid(12, 2.0, 0.0, -1.0, -1.0, [&](const Vec3&) { return v; }));
    const FlowMapStep step = advector.step(mesh, 1.0 / 24.0);
    EXPECT_EQ(step.reset[0], k % 4 == 0) << k;
    EXPECT_EQ(step.reset[1], k == 0 || k % 4 == 2) << k;
    for (int phase = 0; phase < 2; ++phase) {
      if (!step.reset[phase]) continue;
      for (std::size_t i = 0; i < mesh->num_vertices(); ++i) {
        ASSERT_EQ(advector.uv(phase)[i], rest_uv(mesh->positions[i], Axis::Z, advector.tile_size())) << k;
      }
    }
    if (!step.reset[0]) EXPECT_NE(advector.uv(0)[100], rest_uv(mesh->positions[100], Axis::Z, advector.tile_size()));
  }
}

TEST(FlowMap, WeightsSumToOneAndVanishAtReset) {
  for (int period : {2, 3, 5, 16}) {
    for (int step = 0; step < 3 * period; ++step) {
      const auto w = phase_weights(step, period);
      const auto age = phase_ages(step, period);
      EXPECT_NEAR(w[0] + w[1], 1.0, 1e-12) << period << " " << step;
      EXPECT_GE(w[0], 0.0);
      EXPECT_GE(w[1], 0.0);
      EXPECT_EQ(age[0], step % period);
      if (step % period == 0) EXPECT_EQ(w[0], 0.0) << period << " " << step;  // A resets: invisible
      if (age[1] == 0) EXPECT_EQ(w[1], 0.0) << period << " " << step;         // B resets: invisible
      if (period % 2 == 0) {
        const double s = std::sin(std::numbers::pi * (step % period) / period);
        EXPECT_NEAR(w[0], s * s, 1e-12);
        EXPECT_NEAR(w[1], 1.0 - s * s, 1e-12);
      }
    }
    // B's resets are half a period after A's.
    EXPECT_EQ(phase_ages(period / 2, period)[1], 0);
  }
  EXPECT_EQ(rest_uv(Vec3(1, 2, 3), Axis::X, 2.0), Vec2(1.0, 1.5));
  EXPECT_EQ(rest_uv(Vec3(1, 2, 3), Axis::Y, 2.0), Vec2(1.5, 0.5));
  EXPECT_EQ(rest_uv(Vec3(1, 2, 3), Axis::Z, 2.0), Vec2(0.5, 1.0));
}

TEST(FlowMap, SynthesisBlendsBothPhasesOverEveryChartTexel) {
  // The merge scene changes outline and topology every frame.
  SceneOptions so;
  so.frames = 3;
  so.resolution = 24;
  FlowMapAdvector advector(settings(8, 0.0));  // step 2: w = {0.5, 0.5}
  std::vector<std::shared_ptr<const FrameMesh>> meshes;
  for (int f = 1; f <= 3; ++f) {
    meshes.push_back(std::make_shared<const FrameMesh>(make_scene_frame("merge", f, so)));
    advector.step(meshes.back(), 1.0 / so.fps);
  }
  const FlowMapFrame frame = advector.frame();
  EXPECT_NEAR(frame.weight[0], 0.5, 1e-12);
  EXPECT_NEAR(frame.weight[1], 0.5, 1e-12);
  const SurfaceIndex& surface = *advector.shared_surface();
  AtlasOptions ao;
  ao.size = 128;
  const Atlas atlas = build_atlas(surface, ao);
  const TexelMap map = build_texel_map(surface, atlas);
  const Exemplar exemplar(make_exemplar("gravel", 32, 3));
  for (Blend blend : {Blend::Linear, Blend::ContrastPreserving}) {
    const SynthesisResult r = synthesize_flowmap(surface, atlas, map, frame, exemplar, blend, true);
    ASSERT_GT(r.chart_texels, 1000u);
    EXPECT_EQ(r.uncovered_texels, 0u);
    std::size_t checked = 0;
    const int nc = exemplar.channels();
    for (std::size_t i = 0; i < map.face.size(); ++i) {
      if (map.face[i] < 0) continue;
      ASSERT_EQ(r.weight.pixels[i], 1.0f);
      if (i % 37 != 0) continue;  // a sample of the texels, recomputed by hand
      const Tri& t = surface.mesh().triangles[map.face[i]];
      double sum[3] = {0, 0, 0}, sw = 0, sw2 = 0;
      for (int k = 0; k < 2; ++k) {
        const Vec2 uv = map.bary(i)[0] * frame.uv[k][t[0]] + map.bary(i)[1] * frame.uv[k][t[1]] +
                        map.bary(i)[2] * frame.uv[k][t[2]];
        float s[3];
        exemplar.sample(frame.anchor[k].x() + uv.x(), frame.anchor[k].y() + uv.y(), s);
        const double w = frame.weight[k];
        for (int c = 0; c < nc; ++c) sum[c] += w * (blend == Blend::Linear ? s[c] : s[c] - exemplar.mean()[c]);
        sw += w, sw2 += w * w;
      }
      for (int c = 0; c < nc; ++c) {
        const double expected = blend == Blend::Linear ? sum[c] / sw : sum[c] / std::sqrt(sw2) + exemplar.mean()[c];
        EXPECT_NEAR(r.color.pixels[i * nc + c], std::clamp(expected, 0.0, 1.0), 1e-5);
      }
      ++checked;
    }
    EXPECT_GT(checked, 20u);
  }
}

TEST(FlowMap, RunWritesEveryFrameAndIsThreadIndependent) {
  test::TempDir dir;
  std::string out;
  ASSERT_EQ(run_fluidtex("gen merge -o " + q(dir.str()) +
                             " --frames 3 --resolution 20 --exemplar gravel "
                             "--exemplar-pixels 64",
                         &out),
            0)
      << out;
  const std::string base = "run -q --method flowmap --flowmap-period 4 -i " + q(dir.file("merge.####.ply")) + " -e " +
                           q(dir.file("gravel.png")) + " --atlas-size 128 --aov weight ";
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("t1")) + " --threads 1", &out), 0) << out;
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("t2")) + " --threads 2", &out), 0) << out;
  const fs::path o = dir.path() / "t1";
  EXPECT_FALSE(fs::exists(o / "state"));
  for (const char* f : {"atlas.0001.exr", "atlas.0002.exr", "atlas.0003.exr", "mesh.0001.obj", "mesh.0002.obj",
                        "mesh.0003.obj", "aov/weight.0003.exr"}) {
    const std::string a = test::read_file(o / f), b = test::read_file(dir.path() / "t2" / f);
    EXPECT_FALSE(a.empty()) << f;
    EXPECT_TRUE(a == b) << f;
  }
  const std::string stats = test::read_file(o / "stats.jsonl");
  EXPECT_EQ(std::count(stats.begin(), stats.end(), '\n'), 3) << stats;
  EXPECT_EQ(stats.find("{\"frame\":1,\"method\":\"flowmap\","), 0u) << stats;
  EXPECT_NE(stats.find("\"advect\":"), std::string::npos) << stats;
  EXPECT_NE(stats.find("\"synthesis\":"), std::string::npos) << stats;
  EXPECT_EQ(stats.find("\"state\":"), std::string::npos) << stats;
  EXPECT_NE(stats.find("\"packing_efficiency\":"), std::string::npos) << stats;
  EXPECT_EQ(stats.find("\"chart_texels\":0"), std::string::npos) << stats;
  std::size_t uncovered = 0;
  for (std::size_t p = 0; (p = stats.find("\"uncovered_fraction\":0,", p)) != std::string::npos; ++p) ++uncovered;
  EXPECT_EQ(uncovered, 3u) << stats;
}

TEST(FlowMap, BadOptionsAreInputErrors) {
  JobOptions job;
  job.input.pattern = "x.####.ply";
  job.exemplar = "e.png";
  job.output.dir = "out";
  job.method = TexturingMethod::FlowMap;
  EXPECT_NO_THROW(job.validate());
  job.flowmap.period = 1;
  EXPECT_THROW(job.validate(), InputError);
  job.flowmap.period = 16;
  job.output.resume = true;
  EXPECT_THROW(job.validate(), InputError);
  job.output.resume = false;
  job.synthesis.track_only = true;
  EXPECT_THROW(job.validate(), InputError);
  job.synthesis.track_only = false;
  job.output.debug_views = true;
  EXPECT_THROW(job.validate(), InputError);
  EXPECT_THROW(parse_enum<TexturingMethod>("splat", "method"), InputError);
  EXPECT_THROW(parse_enum<Axis>("w", "flowmap-axis"), InputError);
  EXPECT_THROW(FlowMapAdvector(settings(0, 0.1)), InputError);

  test::TempDir dir;
  std::string out;
  ASSERT_EQ(run_fluidtex("gen rotation -o " + q(dir.str()) + " --frames 2 --resolution 10", &out), 0);
  const std::string base = "run -i " + q(dir.file("rotation.####.ply")) + " -e x.png -o " + q(dir.file("out"));
  EXPECT_EQ(run_fluidtex(base + " --method flowmap --flowmap-period 1", &out), 2);
  EXPECT_NE(out.find("--flowmap-period"), std::string::npos) << out;
  EXPECT_EQ(run_fluidtex(base + " --method flowmap --resume", &out), 2);
  EXPECT_NE(out.find("--resume"), std::string::npos) << out;
  EXPECT_EQ(run_fluidtex(base + " --method flowmap --track-only", &out), 2);
  EXPECT_EQ(run_fluidtex(base + " --method splat", &out), 2);
  EXPECT_EQ(run_fluidtex(base + " --method flowmap --flowmap-axis w", &out), 2);
  EXPECT_FALSE(fs::exists(dir.file("out")));
}

}  // namespace
}  // namespace fluidtex
