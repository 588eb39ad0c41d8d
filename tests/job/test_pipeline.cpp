// A run's outputs (job/pipeline.h): atlases name their colour space, build,
// frame and settings; no output of another job survives a run; off a
// terminal every frame logs one line; a frame whose state cannot be written
// leaves nothing; a liquid that grows from a small start is warned of; the
// same --exemplar-size gives scenes of any extent the same texture size;
// UDIM tiles hold what one tile cannot.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "color_fixtures.h"
#include "farm_fixtures.h"
#include "fluidtex/inspect/texture_metrics.h"
#include "fluidtex/inspect/textured_frame.h"
#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/io/image_io.h"
#include "fluidtex/io/uv_mesh_io.h"
#include "fluidtex/job/frame_texturing.h"
#include "fluidtex/job/job_record.h"
#include "fluidtex/job/pipeline.h"
#include "fluidtex/scenes/exemplar_gen.h"
#include "fluidtex/scenes/scenes.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/strings.h"
#include "fluidtex/util/version.h"
#include "mesh_fixtures.h"
#include "test_util.h"

namespace fluidtex {
namespace {

namespace fs = std::filesystem;
using namespace test::farm;
using test::run_fluidtex;

/// The string attributes and the chromaticities of an atlas, as OIIO reads them.
std::map<std::string, std::string> atlas_metadata(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << path;
  std::map<std::string, std::string> out;
  if (!in) return out;
  const OIIO::ImageSpec& spec = in->spec();
  for (const char* name : {"oiio:ColorSpace", "Software", "fluidtex:version", "fluidtex:frame", "fluidtex:settings",
                           "fluidtex:exemplarSize"})
    out[name] = spec.get_string_attribute(name);
  if (const OIIO::ParamValue* p = spec.find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8))) {
    const float* c = static_cast<const float*>(p->data());
    for (int i = 0; i < 8; ++i) out["chromaticities"] += std::to_string(c[i]).substr(0, 6) + " ";
  }
  return out;
}

TEST(Pipeline, AtlasesNameTheirColourSpaceBuildFrameAndSettings) {
  test::TempDir dir;
  const std::string run = scene(dir);
  std::string out;
  ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file("a")) + " --frames 1-2", &out), 0) << out;
  auto meta = atlas_metadata(dir.file("a/atlas.0002.exr"));
  EXPECT_EQ(meta["oiio:ColorSpace"], "Linear");
  EXPECT_EQ(meta["chromaticities"], "0.6400 0.3300 0.3000 0.6000 0.1500 0.0600 0.3127 0.3290 ");
  EXPECT_EQ(meta["fluidtex:version"], version_line());
  EXPECT_EQ(meta["fluidtex:frame"], "2");
  const std::string settings = meta["fluidtex:settings"];
  EXPECT_EQ(settings.size(), 40u);
  EXPECT_EQ(settings, settings_hash(read_job_record(dir.file("a"))));
  // The same job from another folder (paths are not settings) and through
  // track + synth stamps the same; another seed does not.
  test::TempDir elsewhere;
  fs::copy(dir.path(), elsewhere.path() / "in", fs::copy_options::recursive);
  const std::string moved = "run -q -i " + q((elsewhere.path() / "in/rotation.####.ply").string()) + " -e " +
                            q((elsewhere.path() / "in/ex.png").string()) + " --aov weight " + kSettings;
  ASSERT_EQ(run_fluidtex(moved + "-o " + q(elsewhere.file("b")) + " --frames 1-2", &out), 0) << out;
  EXPECT_EQ(atlas_metadata(elsewhere.file("b/atlas.0002.exr"))["fluidtex:settings"], settings);
  EXPECT_EQ(test::read_file(dir.file("a/atlas.0002.exr")), test::read_file(elsewhere.file("b/atlas.0002.exr")));
  ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file("c")) + " --frames 1-2 --track-only", &out), 0) << out;
  ASSERT_EQ(run_fluidtex("synth -q -o " + q(dir.file("c")), &out), 0) << out;
  EXPECT_EQ(atlas_metadata(dir.file("c/atlas.0001.exr"))["fluidtex:settings"],
            atlas_metadata(dir.file("a/atlas.0001.exr"))["fluidtex:settings"]);
  // The exemplar's size on the surface, as job.toml records it, in every
  // atlas, through synth too.
  const std::optional<double> span = read_job_record(dir.file("a")).exemplar_size;
  ASSERT_TRUE(span);
  EXPECT_EQ(meta["fluidtex:exemplarSize"], format_number(*span));
  EXPECT_EQ(atlas_metadata(dir.file("c/atlas.0001.exr"))["fluidtex:exemplarSize"], format_number(*span));
  const std::string reseeded = "run -q -i " + q(dir.file("rotation.####.ply")) + " -e " + q(dir.file("ex.png")) +
                               " --aov weight --atlas-size 128 --seed 4 ";
  ASSERT_EQ(run_fluidtex(reseeded + "-o " + q(dir.file("d")) + " --frames 1-2", &out), 0) << out;
  EXPECT_NE(atlas_metadata(dir.file("d/atlas.0002.exr"))["fluidtex:settings"], settings);
}

TEST(Pipeline, TheSameExemplarSizeGivesScenesOfAnyExtentTheSameTextureSize) {
  // Still sheets 1 and 3 units across. By default the exemplar's span
  // follows each first frame's size; with --exemplar-size both atlases show
  // the texture at that size in scene units, measured from the atlas through
  // the UV mesh.
  test::TempDir dir;
  write_image(dir.file("ex.png"), make_exemplar("gravel", 128, 5));
  for (const int extent : {1, 3})
    write_frame_ply(dir.file("sheet" + std::to_string(extent) + ".0001.ply"), test::flat_grid(24, extent), 24.0);
  const Exemplar exemplar = load_exemplar(dir.file("ex.png"), false);
  struct Span {
    double recorded, measured;
  };
  const auto span_of = [&](int extent, std::optional<double> exemplar_size) {
    JobOptions job;
    job.input.pattern = dir.file("sheet" + std::to_string(extent) + ".####.ply");
    job.exemplar = dir.file("ex.png");
    job.output.dir = dir.file("out" + std::to_string(extent) + (exemplar_size ? "given" : "auto"));
    job.synthesis.atlas.size = 512;
    job.synthesis.exemplar_size = exemplar_size;
    run_job(job, silent_reporter());
    const double recorded = read_job_record(job.output.dir).exemplar_size.value_or(0.0);
    const TexturedFrame frame = read_run_frame(job.output.atlas(), job.output.mesh(), 1);
    return Span{recorded, measured_exemplar_span(frame.atlas.first(), frame.mesh, exemplar, recorded)};
  };
  const Span small = span_of(1, std::nullopt), large = span_of(3, std::nullopt);
  EXPECT_NEAR(large.recorded / small.recorded, 3.0, 1e-9);  // 2.6 × 5 % of each diagonal
  EXPECT_NEAR(small.measured / small.recorded, 1.0, 0.1);
  EXPECT_NEAR(large.measured / large.recorded, 1.0, 0.1);
  const Span given_small = span_of(1, 0.3), given_large = span_of(3, 0.3);
  EXPECT_EQ(given_small.recorded, 0.3);
  EXPECT_EQ(given_large.recorded, 0.3);
  EXPECT_NEAR(given_small.measured / 0.3, 1.0, 0.1);
  EXPECT_NEAR(given_large.measured / 0.3, 1.0, 0.1);
  EXPECT_NEAR(given_large.measured / given_small.measured, 1.0, 0.1);
}

TEST(Pipeline, UdimTilesHoldASurfaceThatOneTileCannot) {
  // The rotation scene (a disk of area π) at 150 texels per scene unit: one
  // 128² tile cannot hold it. With <UDIM> in the atlas patterns every frame
  // writes tiles 1001, 1002, ... of each layer, its material names them by
  // the token, and the texture on the surface is the one a single large
  // enough atlas shows.
  test::TempDir dir;
  const std::string run = scene_run(dir) + "--seed 3 --texel-density 150 --frames 1-3 ";
  std::string out;
  EXPECT_EQ(run_fluidtex(run + "--atlas-size 128 -o " + q(dir.file("one")), &out), 2);
  EXPECT_NE(out.find("put <UDIM> in --atlas for UDIM tiles"), std::string::npos) << out;
  const std::string tiled = run + "--atlas-size 128 -o " + q(dir.file("t")) + " --atlas " +
                            q(dir.file("t/atlas.####.<UDIM>.exr")) + " --displacement-atlas " +
                            q(dir.file("t/h.####.<UDIM>.exr"));
  ASSERT_EQ(run_fluidtex(tiled, &out), 0) << out;
  const FramePattern atlas(dir.file("t/atlas.####.<UDIM>.exr"));
  for (int f = 1; f <= 3; ++f) {
    const std::vector<int> udims = atlas.udims(f);
    ASSERT_GE(udims.size(), 3u) << "frame " << f;
    // Consecutive from 1001; the height and weight layers have the same tiles.
    for (std::size_t i = 0; i < udims.size(); ++i) EXPECT_EQ(udims[i], udim_number(static_cast<int>(i)));
    EXPECT_EQ(FramePattern(dir.file("t/h.####.<UDIM>.exr")).udims(f), udims);
    EXPECT_EQ(FramePattern(dir.file("t/aov/weight.####.<UDIM>.exr")).udims(f), udims);
  }
  const std::string material = test::read_file(dir.file("t/mesh.0002.mtl"));
  EXPECT_NE(material.find("map_Kd atlas.0002.<UDIM>.exr"), std::string::npos) << material;
  EXPECT_NE(material.find("disp h.0002.<UDIM>.exr"), std::string::npos) << material;
  const UVMesh mesh = read_uv_mesh(dir.file("t/mesh.0002.obj"));
  double u_max = 0.0;
  for (const Vec2& uv : mesh.uvs) u_max = std::max(u_max, uv.x());
  EXPECT_GT(u_max, 2.0);
  // The texel density holds across the tiles.
  EXPECT_NEAR(texel_density(mesh, 128), 150.0, 0.5);
  // The same job in one 512² atlas shows the same texture on the surface.
  ASSERT_EQ(run_fluidtex(run + "--atlas-size 512 -o " + q(dir.file("big")), &out), 0) << out;
  EXPECT_EQ(run_fluidtex("compare " + q(dir.file("big")) + " " + q(dir.file("t")), &out), 0) << out;
  EXPECT_NE(out.find("layouts differ"), std::string::npos) << out;
  // A lost tile 1001 makes its frame incomplete: --resume makes it again,
  // every tile the same bytes.
  const std::string kept = test::read_file(atlas.path(2, 1002));
  fs::remove(atlas.path(2, 1001));
  ASSERT_EQ(run_fluidtex(tiled + " --resume", &out), 0) << out;
  EXPECT_EQ(test::read_file(atlas.path(2, 1002)), kept);
  EXPECT_TRUE(fs::exists(atlas.path(2, 1001)));
  // Texel by texel, the tiles of the same job on one thread pass; a damaged
  // texel of tile 1002 is found and named.
  const std::string again = run + "--atlas-size 128 -o " + q(dir.file("t1")) + " --atlas " +
                            q(dir.file("t1/atlas.####.<UDIM>.exr")) + " --threads 1";
  ASSERT_EQ(run_fluidtex(again, &out), 0) << out;
  EXPECT_EQ(run_fluidtex("compare " + q(dir.file("t")) + " " + q(dir.file("t1")), &out), 0) << out;
  Image damaged = read_image(dir.file("t1/atlas.0001.1002.exr"));
  const std::vector<char> charts = chart_mask(mesh, 128, udim_origin(1002));
  const auto texel = static_cast<std::size_t>(std::find(charts.begin(), charts.end(), 1) - charts.begin());
  ASSERT_LT(texel, charts.size());
  damaged.pixel(texel)[0] = damaged.pixel(texel)[0] > 0.5f ? 0.0f : 1.0f;
  write_image(dir.file("t1/atlas.0001.1002.exr"), damaged);
  EXPECT_EQ(run_fluidtex("compare " + q(dir.file("t")) + " " + q(dir.file("t1")), &out), 1) << out;
  EXPECT_NE(out.find("frame 1: worst texel (" + std::to_string(texel % 128) + ", " + std::to_string(texel / 128) +
                     ") of tile 1002"),
            std::string::npos)
      << out;
  // The layers share the atlas's tiles; meshes have none.
  EXPECT_EQ(run_fluidtex(run + "-o " + q(dir.file("x")) + " --atlas " + q(dir.file("x/a.####.<UDIM>.exr")) +
                             " --normal-atlas " + q(dir.file("x/n.####.exr")),
                         &out),
            2);
  EXPECT_NE(out.find("put <UDIM> in its pattern too"), std::string::npos) << out;
  EXPECT_EQ(run_fluidtex(run + "-o " + q(dir.file("x")) + " --mesh " + q(dir.file("x/m.####.<UDIM>.obj")), &out), 2);
  EXPECT_NE(out.find("<UDIM> names the tiles of a texture, not of a mesh"), std::string::npos) << out;
}

TEST(Pipeline, AnExemplarInAnotherColourSpaceIsConvertedOnce) {
  // A one-colour exemplar in `wide` (as an ACEScg texture would be), blended
  // in lin_a: every chart texel of the atlas is its colour converted once
  // (Eq. 7 of one colour is that colour), and the atlas names lin_a; with
  // --output-colorspace wide, the colour as the exemplar has it.
  test::TempDir dir;
  test::write_file(dir.path() / "test.ocio", test::kTwoSpaceConfig);
  test::write_swatch(dir.file("wide.exr"), "wide", false);
  write_frame_ply(dir.file("sheet.0001.ply"), test::flat_grid(12), 24.0);
  for (const std::string output : {"", "wide"}) {
    SCOPED_TRACE("--output-colorspace '" + output + "'");
    JobOptions job;
    job.input.pattern = dir.file("sheet.####.ply");
    job.exemplar = dir.file("wide.exr");
    job.output.dir = dir.file("out" + output);
    job.synthesis.atlas.size = 128;
    job.synthesis.float_output = true;
    job.synthesis.color.config = dir.file("test.ocio");
    job.synthesis.color.working = "lin_a";
    job.synthesis.color.output = output;
    run_job(job, silent_reporter());
    const ImageFile atlas = read_image_file(FramePattern(job.output.atlas()).path(1), ImageValues::AsStored);
    EXPECT_EQ(atlas.color_space, output.empty() ? "lin_a" : "wide");
    const std::array<float, 3> expected =
        output.empty() ? test::wide_to_lin_a(0.2f, 0.4f, 0.8f) : std::array<float, 3>{0.2f, 0.4f, 0.8f};
    const std::vector<char> charts = chart_mask(read_uv_mesh(FramePattern(job.output.mesh()).path(1)), 128);
    int texels = 0, off = 0;
    for (std::size_t i = 0; i < charts.size(); ++i) {
      if (!charts[i]) continue;
      ++texels;
      for (int c = 0; c < 3; ++c) off += std::abs(atlas.image.pixel(i)[c] - expected[c]) > 1e-6f;
    }
    EXPECT_GT(texels, 1000);
    EXPECT_EQ(off, 0);
    // The job holds the config's content: an edited config is another job.
    const JobRecord record = read_job_record(job.output.dir);
    EXPECT_EQ(record.ocio_sha1, file_sha1(dir.file("test.ocio")));
    job.input.fps = record.options.input.fps;  // as the run recorded it
    EXPECT_NO_THROW(check_resumable(record, make_job_record(job, record.frames)));
    test::write_file(dir.path() / "edited.ocio", std::string(test::kTwoSpaceConfig) + "# edited\n");
    job.synthesis.color.config = dir.file("edited.ocio");
    EXPECT_THROW(check_resumable(record, make_job_record(job, record.frames)), InputError);
  }
}

TEST(Pipeline, ARunNeverLeavesAnotherJobsOutputsBehind) {
  test::TempDir dir;
  const std::string bare = scene_run(dir), run = bare + kSettings;
  const std::string out_dir = dir.file("out");
  std::string out;
  ASSERT_EQ(run_fluidtex(run + "-o " + q(out_dir) + " --debug-views", &out), 0) << out;
  ASSERT_EQ(run_fluidtex("preview " + q(out_dir) + " --width 16 --frames 6", &out), 0) << out;
  // Without --force: refused, nothing touched.
  const std::vector<std::string> before = test::list_dir(out_dir);
  EXPECT_EQ(run_fluidtex(run + "-o " + q(out_dir) + " --frames 1-3", &out), 2) << out;
  EXPECT_NE(out.find("job.toml and "), std::string::npos) << out;
  EXPECT_NE(out.find("--force replaces it"), std::string::npos) << out;
  EXPECT_EQ(test::list_dir(out_dir), before);
  // With --force: the earlier job's files are gone, frames 4-6 included.
  ASSERT_EQ(run_fluidtex(bare + "--atlas-size 128 -o " + q(out_dir) + " --frames 1-3 --force --seed 5", &out), 0)
      << out;
  for (const char* gone : {"atlas.0004.exr", "mesh.0006.obj", "mesh.0006.mtl", "state/patches.0005.bin",
                           "aov/weight.0006.exr", "debug/patches.0001.ply", "preview/frame.0006.png"}) {
    EXPECT_FALSE(fs::exists(dir.path() / "out" / gone)) << gone;
  }
  EXPECT_TRUE(fs::exists(dir.path() / "out" / "atlas.0003.exr"));
  const std::string stats = test::read_file(dir.path() / "out" / "stats.jsonl");
  EXPECT_EQ(std::count(stats.begin(), stats.end(), '\n'), 3) << stats;
  EXPECT_EQ(read_job_record(out_dir).frames, (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(read_job_record(out_dir).options.seed, 5u);
  EXPECT_EQ(read_job_record(out_dir).exemplar_sha1, file_sha1(dir.file("ex.png")));
  // An input is never an output, not even with --force.
  test::write_rotation_scene(dir.path() / "in", 2, 8);
  const std::string in = dir.file("in/rotation.####.ply");
  EXPECT_EQ(run_fluidtex("run -q -i " + q(in) + " -e " + q(dir.file("ex.png")) + " -o " + q(dir.file("in")) +
                             " --mesh " + q(in) + " --force",
                         &out),
            2);
  EXPECT_NE(out.find("--mesh would overwrite the input frames"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(dir.path() / "in" / "rotation.0002.ply"));
  // --resume and --force together make no sense.
  EXPECT_EQ(run_fluidtex(run + "-o " + q(out_dir) + " --resume --force", &out), 2) << out;
}

TEST(Pipeline, OffATerminalEveryFrameLogsOneLine) {
  test::TempDir dir;
  const std::string run = scene(dir);
  std::string out;
  // run_fluidtex captures stderr through a pipe: not a terminal.
  ASSERT_EQ(run_fluidtex(run.substr(0, run.find(" -q")) + run.substr(run.find(" -q") + 3) + "-o " + q(dir.file("a")) +
                             " --track-only",
                         &out),
            0)
      << out;
  const std::regex text_line(R"(track frame (\d+): \d+\.\d{3} s, \d+ patches)");
  std::istringstream lines(out);
  std::vector<int> logged;
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (std::regex_match(line, m, text_line)) logged.push_back(std::stoi(m[1]));
  }
  EXPECT_EQ(logged, (std::vector<int>{1, 2, 3, 4, 5, 6})) << out;
  // JSON: every line an object; frames in order; the error too.
  ASSERT_EQ(run_fluidtex("synth -o " + q(dir.file("a")) + " --frames 2-3 --log-format json", &out), 0) << out;
  const std::regex json_frame(R"(\{"event":"frame","step":"synth","frame":(\d+),"seconds":\d+\.\d{3},"patches":\d+\})");
  std::istringstream json(out);
  logged.clear();
  for (std::string line; std::getline(json, line);) {
    EXPECT_TRUE(line.starts_with("{\"event\":\"") && line.ends_with("}")) << line;
    std::smatch m;
    if (std::regex_match(line, m, json_frame)) logged.push_back(std::stoi(m[1]));
  }
  EXPECT_EQ(logged, (std::vector<int>{2, 3})) << out;
  EXPECT_EQ(run_fluidtex("synth -o " + q(dir.file("a")) + " --frames 9 --log-format json", &out), 2);
  EXPECT_TRUE(out.starts_with("{\"event\":\"error\",\"internal\":false,\"message\":\"")) << out;
  // -q: nothing but warnings and errors.
  ASSERT_EQ(run_fluidtex("synth -q -o " + q(dir.file("a")) + " --frames 1", &out), 0) << out;
  EXPECT_EQ(out, "");
}

/// A frame is complete with its state or absent: when the state cannot be
/// written (here a folder is in its way; disk full or a read-only state/ are
/// the same), the atlas and mesh of that frame and of the frames in flight
/// behind it are removed again.
TEST(Pipeline, FrameWhoseStateFailsLeavesNoAtlasOrMesh) {
  test::TempDir dir;
  test::write_rotation_scene(dir.path(), 3, 8, "ex.png", 16);
  JobOptions job;
  job.input.pattern = dir.file("rotation.####.ply");
  job.exemplar = dir.file("ex.png");
  job.output.dir = dir.file("out");
  job.synthesis.atlas.size = 64;
  job.output.debug_views = true;
  std::filesystem::create_directories(dir.path() / "out" / "state" / "patches.0002.bin");
  EXPECT_THROW(run_job(job, silent_reporter()), InternalError);
  const auto out = dir.path() / "out";
  EXPECT_TRUE(std::filesystem::exists(out / "atlas.0001.exr"));
  EXPECT_TRUE(std::filesystem::exists(out / "debug" / "patches.0001.ply"));
  EXPECT_TRUE(std::filesystem::exists(out / "state" / "patches.0001.bin"));
  for (const char* name : {"atlas.0002.exr", "mesh.0002.obj", "atlas.0003.exr", "mesh.0003.obj",
                           "debug/patches.0002.ply", "debug/disks.0002.ply", "debug/patches.0003.ply"})
    EXPECT_FALSE(std::filesystem::exists(out / name)) << name;  // frame 3 may have been in flight
}

/// Keeps the warnings a run gives.
struct WarningLog : Reporter {
  std::vector<std::string> warnings;
  void warn(const std::string& message) override { warnings.push_back(message); }
};

TEST(Pipeline, LiquidThatGrowsFromASmallStartIsWarnedOfOnceUnlessTheRadiusIsGiven) {
  // A flat sheet spreading from 0.25 to 0.85 across in three frames (its
  // area 11.6 times the first's): the automatic radius comes from the first
  // frame, so the patches multiply. One warning says so and what to do.
  test::TempDir dir;
  const std::vector<double> sizes = {0.25, 0.45, 0.65, 0.85};
  const double fps = 24.0;
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    const double rate = i + 1 < sizes.size() ? (sizes[i + 1] / sizes[i] - 1.0) * fps : 0.0;
    const FrameMesh sheet = test::flat_grid(24, sizes[i], 0.0, 0.0, 0.0, [&](const Vec3& p) { return rate * p; });
    write_frame_ply(dir.file(FramePattern("sheet.####.ply").path(static_cast<int>(i) + 1)), sheet, fps);
  }
  JobOptions job;
  job.input.pattern = dir.file("sheet.####.ply");
  job.output.dir = dir.file("auto");
  job.synthesis.track_only = true;
  WarningLog log;
  run_job(job, log);
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_TRUE(log.warnings[0].starts_with("frame 4: the liquid's surface is 11.6 times frame 1's")) << log.warnings[0];
  EXPECT_NE(log.warnings[0].find("give --radius"), std::string::npos) << log.warnings[0];
  job.output.dir = dir.file("given");
  job.tracking.radius = 0.05;
  WarningLog quiet;
  run_job(job, quiet);
  EXPECT_TRUE(quiet.warnings.empty());
}
}  // namespace
}  // namespace fluidtex
