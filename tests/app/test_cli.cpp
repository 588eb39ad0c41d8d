// End-to-end tests of the fluidtex executable: subcommands, exit codes,
// error messages and the promise that bad input leaves no output behind.
#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "fluidtex/inspect/compare.h"
#include "fluidtex/inspect/eval.h"
#include "fluidtex/inspect/preview.h"
#include "fluidtex/io/image_io.h"
#include "fluidtex/io/mesh_io.h"
#include "fluidtex/job/job_options.h"
#include "fluidtex/job/synth_job.h"
#include "fluidtex/scenes/example.h"
#include "fluidtex/scenes/scenes.h"
#include "fluidtex/tracking/tracker.h"
#include "fluidtex/util/version.h"
#include "test_util.h"

namespace fluidtex {
namespace {

namespace fs = std::filesystem;
using test::run_fluidtex;

std::string q(const std::string& s) { return "'" + s + "'"; }

/// Generates the rotation scene with a gravel exemplar in `dir` and returns
/// the start of a `run` command line over it (without -o).
std::string rotation_run(const test::TempDir& dir, int frames, int resolution, int exemplar_size, int atlas_size) {
  std::string out;
  EXPECT_EQ(run_fluidtex("gen rotation -o " + q(dir.str()) + " --frames " + std::to_string(frames) + " --resolution " +
                             std::to_string(resolution) + " --exemplar gravel --exemplar-pixels " +
                             std::to_string(exemplar_size),
                         &out),
            0)
      << out;
  return "run -q -i " + q(dir.file("rotation.####.ply")) + " -e " + q(dir.file("gravel.png")) + " --atlas-size " +
         std::to_string(atlas_size) + " ";
}

TEST(Cli, HelpAndVersion) {
  std::string out;
  EXPECT_EQ(run_fluidtex("--help", &out), 0);
  EXPECT_NE(out.find("run"), std::string::npos);
  EXPECT_NE(out.find("info"), std::string::npos);
  EXPECT_NE(out.find("gen"), std::string::npos);
  EXPECT_EQ(run_fluidtex("run --help", &out), 0);
  EXPECT_NE(out.find("--plane-angle"), std::string::npos);
  EXPECT_NE(out.find("--fade-frames"), std::string::npos);
  EXPECT_NE(out.find("48"), std::string::npos);  // defaults are shown
  EXPECT_EQ(run_fluidtex("--version", &out), 0);
  EXPECT_EQ(out, version_line() + "\n");
}

/// --version and every job.toml name the build: the version and, from a git
/// checkout (this test's source tree is one when .git is there), the commit.
TEST(Cli, VersionNamesTheBuild) {
  EXPECT_EQ(std::string(version()), FLUIDTEX_TEST_PROJECT_VERSION);
  const std::string line = version_line();
  EXPECT_EQ(line.rfind(std::string("fluidtex ") + version(), 0), 0u) << line;
  if (std::filesystem::exists(std::filesystem::path(FLUIDTEX_SOURCE_DIR) / ".git")) {
    const std::string commit = git_commit();
    ASSERT_GE(commit.size(), 12u) << line;
    for (std::size_t i = 0; i < 12; ++i) EXPECT_TRUE(std::isxdigit(static_cast<unsigned char>(commit[i]))) << commit;
    EXPECT_NE(line.find("(git " + commit + ")"), std::string::npos) << line;
  }
  JobOptions job;
  EXPECT_EQ(job_toml(job).rfind("# " + line + "\n", 0), 0u);
}

TEST(Cli, UnknownOptionIsBadInput) {
  std::string out;
  EXPECT_EQ(run_fluidtex("run --no-such-option", &out), 2);
  EXPECT_EQ(run_fluidtex("", &out), 2);
}

TEST(Cli, GenThenInfo) {
  test::TempDir dir;
  std::string out;
  ASSERT_EQ(run_fluidtex("gen rotation -o " + q(dir.file("rot")) + " --frames 3 --resolution 12", &out), 0) << out;
  EXPECT_EQ(test::list_dir(dir.path() / "rot"),
            (std::vector<std::string>{"rotation.0001.ply", "rotation.0002.ply", "rotation.0003.ply"}));
  ASSERT_EQ(run_fluidtex("info -i " + q(dir.file("rot/rotation.####.ply")), &out), 0) << out;
  EXPECT_NE(out.find("3 frames (1..3)"), std::string::npos) << out;
  EXPECT_NE(out.find("|velocity|"), std::string::npos) << out;
  EXPECT_NE(out.find("bounding box"), std::string::npos) << out;
}

TEST(Cli, GenUnknownSceneIsBadInput) {
  test::TempDir dir;
  std::string out;
  EXPECT_EQ(run_fluidtex("gen volcano -o " + q(dir.file("x")), &out), 2);
  EXPECT_NE(out.find("volcano"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir.file("x")) && !fs::is_empty(dir.file("x")));
}

TEST(Cli, InfoReportsABadFrameAndExits2) {
  test::TempDir dir;
  std::string out;
  ASSERT_EQ(run_fluidtex("gen rotation -o " + q(dir.str()) + " --frames 2 --resolution 10", &out), 0) << out;
  test::write_file(dir.path() / "rotation.0003.ply", "ply\nformat ascii 1.0\nelement vertex 3\n");
  EXPECT_EQ(run_fluidtex("info -i " + q(dir.file("rotation.####.ply")), &out), 2);
  EXPECT_NE(out.find("rotation.0003.ply"), std::string::npos) << out;
  EXPECT_NE(out.find("ERROR"), std::string::npos) << out;
  EXPECT_NE(out.find("texture size: by default one exemplar tile spans 0.3667 scene units (2.6 x --radius 0.141"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("set --exemplar-size (e.g. 0.37)"), std::string::npos) << out;
  // --json: one document, the same facts for scripts.
  EXPECT_EQ(run_fluidtex("info --json -i " + q(dir.file("rotation.####.ply")), &out), 2);
  EXPECT_TRUE(out.starts_with("{\"sequence\":\"" + dir.file("rotation.####.ply") +
                              "\",\"fps\":24,\"fps_source\":\"header\",\"frames\":[{"))
      << out;
  // The texture's default size on the sequence (from the first frame: the
  // radius 5 % of its diagonal, the tile 2.6 times that), and the value
  // suggested for --exemplar-size.
  EXPECT_NE(out.find("],\"errors\":1,\"texture_scale\":{\"radius\":"), std::string::npos) << out;
  EXPECT_TRUE(out.ends_with("\"suggested_exemplar_size\":0.37}}\n")) << out;
  EXPECT_NE(out.find("{\"frame\":1,\"path\":"), std::string::npos) << out;
  EXPECT_NE(out.find("\"error\":null,\"vertices\":"), std::string::npos) << out;
  EXPECT_NE(out.find("{\"frame\":3,\"path\":\"" + dir.file("rotation.0003.ply") + "\",\"error\":\""), std::string::npos)
      << out;
  EXPECT_NE(out.find("\"speed\":{\"min\":"), std::string::npos) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '{'), std::count(out.begin(), out.end(), '}')) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
}

TEST(Cli, RunMissingInputIsOneLineErrorAndNoOutput) {
  test::TempDir dir;
  std::string out;
  EXPECT_EQ(run_fluidtex("run --track-only -i " + q(dir.file("none.####.ply")) + " -o " + q(dir.file("out")), &out), 2);
  EXPECT_NE(out.find("none.####.ply"), std::string::npos) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  EXPECT_FALSE(fs::exists(dir.file("out")));
}

TEST(Cli, RunUnreadableExemplarIsBadInputAndNoOutput) {
  test::TempDir dir;
  std::string out;
  ASSERT_EQ(run_fluidtex("gen rotation -o " + q(dir.str()) + " --frames 2 --resolution 10", &out), 0);
  test::write_file(dir.path() / "tex.png", "not an image");
  EXPECT_EQ(run_fluidtex("run -q -i " + q(dir.file("rotation.####.ply")) + " -e " + q(dir.file("tex.png")) + " -o " +
                             q(dir.file("out")),
                         &out),
            2);
  EXPECT_NE(out.find("tex.png"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir.file("out")));
}

TEST(Cli, RunRejectsBadOptionValues) {
  test::TempDir dir;
  std::string out;
  ASSERT_EQ(run_fluidtex("gen rotation -o " + q(dir.str()) + " --frames 2 --resolution 10", &out), 0);
  const std::string base = "run -i " + q(dir.file("rotation.####.ply")) + " -o " + q(dir.file("out"));
  EXPECT_EQ(run_fluidtex(base + " --max-distortion 0.5", &out), 2);
  EXPECT_NE(out.find("--max-distortion"), std::string::npos) << out;
  EXPECT_EQ(run_fluidtex(base + " --criterion cube", &out), 2);
  EXPECT_EQ(run_fluidtex(base + " --atlas " + q(dir.file("a.exr")), &out), 2);  // no frame token
  EXPECT_EQ(run_fluidtex(base + " --mesh " + q(dir.file("m.####.fbx")), &out), 2);
  EXPECT_FALSE(fs::exists(dir.file("out")));
}

TEST(Cli, EveryNumberRefusesNaNAndValuesOutOfRange) {
  // Checked while the command line is parsed: no folder is needed to be refused.
  for (const char* args : {"compare a b --mean-tolerance nan", "compare a b --percentile nan",
                           "compare a b --percentile-tolerance inf", "compare a b --samples 5",
                           "preview r --velocity-scale nan", "preview r --width 0", "eval -o r --flow-max-motion nan",
                           "eval -o r --images -1", "eval -o r --warping-bad nan", "eval -o r --threads nan"}) {
    std::string out;
    EXPECT_EQ(run_fluidtex(args, &out), 2) << args << ": " << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << args << ": " << out;
  }
  // compare and eval log as run and synth do.
  std::string out;
  EXPECT_EQ(run_fluidtex("compare nowhere elsewhere --log-format json", &out), 2);
  EXPECT_EQ(out.rfind("{\"event\":\"error\"", 0), 0u) << out;
  EXPECT_EQ(run_fluidtex("eval -o nowhere --log-format json", &out), 2);
  EXPECT_EQ(out.rfind("{\"event\":\"error\"", 0), 0u) << out;
}

/// The options of every command, as their tables list them (the console and
/// config options the CLI binds itself are not among them).
std::map<std::string, std::vector<OptionInfo>> command_tables() {
  std::map<std::string, std::vector<OptionInfo>> tables;
  const auto collect = [&tables](const char* command) {
    return [&tables, command](const OptionInfo& info, const auto&) { tables[command].push_back(info); };
  };
  JobOptions job;
  JobOptions::for_each_option(job, collect("run"));
  SynthRequest synth;
  SynthRequest::for_each_option(synth, collect("synth"));
  EvalOptions eval;
  EvalOptions::for_each_option(eval, collect("eval"));
  CompareOptions compare;
  CompareOptions::for_each_option(compare, collect("compare"));
  PreviewOptions preview;
  PreviewOptions::for_each_option(preview, collect("preview"));
  ExampleRequest gen;
  ExampleRequest::for_each_option(gen, collect("gen"));
  return tables;
}

TEST(Cli, AFlagMeansOneThingInEveryCommand) {
  std::map<std::string, std::string> meaning;  // short flag -> long name
  for (const auto& [command, table] : command_tables()) {
    std::set<std::string> names;
    for (const OptionInfo& info : table) {
      EXPECT_TRUE(names.insert(info.name).second) << command << ": --" << info.name << " twice";
      if (*info.alias == '\0') continue;
      const auto [it, fresh] = meaning.emplace(info.alias, info.name);
      EXPECT_EQ(it->second, info.name) << command << ": " << info.alias << " is --" << info.name << " here";
    }
  }
  EXPECT_EQ(meaning.at("-o"), shared_options::kOutput.name);
  EXPECT_EQ(meaning.at("-i"), shared_options::kInput.name);
  EXPECT_EQ(meaning.at("-e"), shared_options::kExemplar.name);
}

TEST(Cli, NoTwoOutputsShareAFileAndNoOutputOverwritesAnInput) {
  test::TempDir dir;
  const std::string base = rotation_run(dir, 2, 12, 32, 64) + "-o " + q(dir.file("o")) + " ";
  std::string out;
  EXPECT_EQ(run_fluidtex(base + "--atlas " + q(dir.file("o/a.####.exr")) + " --displacement-atlas " +
                             q(dir.file("o/a.%04d.exr")),
                         &out),
            2);
  EXPECT_NE(out.find("--atlas and --displacement-atlas would write the same file"), std::string::npos) << out;
  EXPECT_EQ(run_fluidtex(base + "--mesh " + q(dir.file("rotation.####.ply")), &out), 2);
  EXPECT_NE(out.find("--mesh would overwrite the input frames"), std::string::npos) << out;
  EXPECT_EQ(
      run_fluidtex(base + "--atlas " + q(dir.file("o/x.####.png")) + " --mesh " + q(dir.file("o/x.####.obj")), &out),
      0)
      << out;  // an atlas and a mesh may share a stem
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 0) << out;
  const std::string before = test::read_file(dir.file("rotation.0001.ply"));
  EXPECT_FALSE(before.empty());
  EXPECT_FALSE(fs::exists(dir.path() / "o" / "a.0001.exr"));
}

TEST(Cli, ABinaryOrEmptyJobFileIsNamedNotEchoed) {
  test::TempDir dir;
  std::string bytes;
  for (int i = 0; i < 3000; ++i) bytes += static_cast<char>((i * 131 + 7) % 256);  // binary, NULs included
  test::write_file(dir.path() / "bin.toml", bytes);
  std::string out;
  EXPECT_EQ(run_fluidtex("run -i x.####.ply -o " + q(dir.file("o")) + " --config " + q(dir.file("bin.toml")), &out), 2);
  EXPECT_NE(out.find("bin.toml: not a TOML text file (binary data)"), std::string::npos) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  EXPECT_LT(out.size(), 200u) << out;
  fs::create_directories(dir.path() / "job");
  test::write_file(dir.path() / "job" / "job.toml", "");
  EXPECT_EQ(run_fluidtex("synth -o " + q(dir.file("job")), &out), 2);
  EXPECT_NE(out.find("job.toml: empty: not a job record"), std::string::npos) << out;
  test::write_file(dir.path() / "job" / "job.toml", bytes);
  EXPECT_EQ(run_fluidtex("synth -o " + q(dir.file("job")), &out), 2);
  EXPECT_NE(out.find("job.toml: not a TOML text file (binary data)"), std::string::npos) << out;
  EXPECT_LT(out.size(), 200u) << out;
}

TEST(Cli, PrintConfigRoundTripsThroughConfigFile) {
  test::TempDir dir;
  std::string out;
  ASSERT_EQ(run_fluidtex("run -i x.####.ply -o o --radius 0.125 --fade-frames 30 --print-config", &out), 0);
  EXPECT_NE(out.find("radius=0.125"), std::string::npos) << out;
  EXPECT_NE(out.find("fade-frames=30"), std::string::npos) << out;
  test::write_file(dir.path() / "params.toml", "radius = 0.25\nfade-frames = 12\ncriterion = \"sphere\"\n");
  ASSERT_EQ(run_fluidtex("run -i x.####.ply -o o --config " + q(dir.file("params.toml")) + " --print-config", &out), 0)
      << out;
  EXPECT_NE(out.find("radius=0.25"), std::string::npos) << out;
  EXPECT_NE(out.find("fade-frames=12"), std::string::npos) << out;
  EXPECT_NE(out.find("criterion=\"sphere\""), std::string::npos) << out;
  EXPECT_EQ(run_fluidtex("run -i x.####.ply -o o --config " + q(dir.file("missing.toml")), &out), 2);
}

/// `--print-config` output read back by `--config` gives the same
/// configuration, and a run from it works (an empty list option once failed).
TEST(Cli, PrintConfigOutputReadsBackUnchanged) {
  test::TempDir dir;
  const std::string run = rotation_run(dir, 2, 12, 32, 64);
  std::string printed, again, out;
  ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file("o")) + " --seed 7 --fading density --print-config", &printed), 0)
      << printed;
  test::write_file(dir.path() / "p.toml", printed);
  ASSERT_EQ(run_fluidtex("run --config " + q(dir.file("p.toml")) + " --print-config", &again), 0) << again;
  EXPECT_EQ(again, printed);
  EXPECT_EQ(run_fluidtex("run --config " + q(dir.file("p.toml")), &out), 0) << out;
  EXPECT_TRUE(fs::exists(dir.path() / "o" / "atlas.0002.exr"));
}

TEST(Cli, RunWritesEveryOutputPerFrame) {
  test::TempDir dir;
  std::string out;
  ASSERT_EQ(run_fluidtex("gen rotation -o " + q(dir.str()) +
                             " --frames 3 --resolution 16 --exemplar gravel "
                             "--exemplar-pixels 64",
                         &out),
            0)
      << out;
  ASSERT_EQ(run_fluidtex("run -q -i " + q(dir.file("rotation.####.ply")) + " -e " + q(dir.file("gravel.png")) + " -o " +
                             q(dir.file("out")) + " --atlas-size 128 --aov weight,count --debug-views",
                         &out),
            0)
      << out;
  const fs::path o = dir.path() / "out";
  for (int f = 1; f <= 3; ++f) {
    const std::string n = "000" + std::to_string(f);
    EXPECT_TRUE(fs::exists(o / ("atlas." + n + ".exr"))) << n;
    EXPECT_TRUE(fs::exists(o / ("mesh." + n + ".obj"))) << n;
    EXPECT_TRUE(fs::exists(o / "state" / ("patches." + n + ".bin"))) << n;
    EXPECT_TRUE(fs::exists(o / "aov" / ("weight." + n + ".exr"))) << n;
    EXPECT_TRUE(fs::exists(o / "aov" / ("count." + n + ".exr"))) << n;
    EXPECT_TRUE(fs::exists(o / "debug" / ("disks." + n + ".ply"))) << n;
    // The OBJ names its atlas through a material, relative to its folder.
    const std::string obj = test::read_file(o / ("mesh." + n + ".obj"));
    EXPECT_NE(obj.find("mtllib mesh." + n + ".mtl\n"), std::string::npos) << n;
    EXPECT_NE(obj.find("usemtl "), std::string::npos) << n;
    const std::string mtl = test::read_file(o / ("mesh." + n + ".mtl"));
    EXPECT_NE(mtl.find("\nmap_Kd atlas." + n + ".exr\n"), std::string::npos) << mtl;
  }
  const std::string stats = test::read_file(o / "stats.jsonl");
  EXPECT_EQ(std::count(stats.begin(), stats.end(), '\n'), 3) << stats;
  EXPECT_NE(stats.find("\"frame\":1,"), std::string::npos) << stats;
  EXPECT_NE(stats.find("\"patches\":{\"fading_in\":"), std::string::npos) << stats;
  EXPECT_NE(stats.find("\"uncovered_fraction\":0,"), std::string::npos) << stats;
  // The preview renders the finished frames.
  ASSERT_EQ(run_fluidtex("preview " + q(o.string()) + " --frames 2-3 --width 64", &out), 0) << out;
  EXPECT_TRUE(fs::exists(o / "preview" / "frame.0002.png"));
  EXPECT_TRUE(fs::exists(o / "preview" / "frame.0003.png"));
  // Overlays read the input job.toml records; without a job.toml they need -i.
  ASSERT_EQ(run_fluidtex("preview " + q(o.string()) + " --frames 3 --width 32 --overlay borders", &out), 0) << out;
  fs::rename(o / "job.toml", dir.path() / "job.toml");
  EXPECT_EQ(run_fluidtex("preview " + q(o.string()) + " --overlay borders", &out), 2);
  EXPECT_NE(out.find("-i/--input"), std::string::npos) << out;
  fs::rename(dir.path() / "job.toml", o / "job.toml");
  // A perspective contact sheet of frames 1 and 3, with -i given.
  EXPECT_EQ(run_fluidtex("preview " + q(o.string()) + " --camera 1,2,3", &out), 2);
  ASSERT_EQ(run_fluidtex("preview " + q(o.string()) +
                             " --width 40 --height 30 --camera 0,-3,2,0,0,0,35 "
                             "--overlay borders,states,velocity -i " +
                             q(dir.file("rotation.####.ply")) + " --sheet 2 --sheet-only",
                         &out),
            0)
      << out;
  const Image sheet = read_image((o / "preview" / "sheet.png").string());
  EXPECT_EQ(sheet.width, 2 * 40 + 3 * 4);  // frames 1 and 3 side by side
  EXPECT_EQ(sheet.height, 30 + 2 * 4);
  // No temporary file is left anywhere.
  for (const auto& e : fs::recursive_directory_iterator(o)) {
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
  }
}

TEST(Cli, ResumeContinuesFromTheLastState) {
  test::TempDir dir;
  std::string out;
  const std::string base = rotation_run(dir, 4, 12, 32, 64);
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("full")), &out), 0) << out;
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("part")) + " --frames 1-2", &out), 0) << out;
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("part")) + " --resume", &out), 0) << out;
  for (const char* f : {"atlas.0003.exr", "atlas.0004.exr", "mesh.0004.obj", "state/patches.0004.bin"}) {
    EXPECT_EQ(test::read_file(dir.path() / "full" / f), test::read_file(dir.path() / "part" / f)) << f;
  }
  const std::string stats = test::read_file(dir.path() / "part" / "stats.jsonl");
  EXPECT_EQ(std::count(stats.begin(), stats.end(), '\n'), 4) << stats;
}

TEST(Cli, ResumeMakesAgainAFrameLostInTheMiddle) {
  // A frame of a finished job deleted after the fact (its outputs and its
  // state): --resume makes it and every frame after it again, the same bytes.
  test::TempDir dir;
  std::string out;
  const std::string base = rotation_run(dir, 5, 12, 32, 64);
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("full")), &out), 0) << out;
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("holed")), &out), 0) << out;
  for (const char* f : {"atlas.0003.exr", "mesh.0003.obj", "mesh.0003.mtl", "state/patches.0003.bin"})
    fs::remove(dir.path() / "holed" / f);
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("holed")) + " --resume", &out), 0) << out;
  for (const char* f :
       {"atlas.0003.exr", "mesh.0003.obj", "state/patches.0003.bin", "atlas.0005.exr", "state/patches.0005.bin"}) {
    const std::string made = test::read_file(dir.path() / "holed" / f);
    EXPECT_FALSE(made.empty()) << f;
    EXPECT_TRUE(made == test::read_file(dir.path() / "full" / f)) << f;
  }
}

TEST(Cli, TheFrameRateIsTheOneTheInputStatesUnlessGiven) {
  // gen --fps 12 states the rate in every frame's header; run takes it from
  // there, records it in job.toml, and warns when --fps says otherwise.
  test::TempDir dir;
  std::string out;
  ASSERT_EQ(run_fluidtex("gen rotation -o " + q(dir.str()) +
                             " --frames 3 --resolution 12 --fps 12 --exemplar gravel --exemplar-pixels 32",
                         &out),
            0)
      << out;
  ASSERT_EQ(run_fluidtex("info --json -i " + q(dir.file("rotation.####.ply")), &out), 0) << out;
  EXPECT_NE(out.find("\"fps\":12,\"fps_source\":\"header\""), std::string::npos) << out;
  const std::string base =
      "run -i " + q(dir.file("rotation.####.ply")) + " -e " + q(dir.file("gravel.png")) + " --atlas-size 64 ";
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("stated")), &out), 0) << out;
  EXPECT_NE(out.find("12 fps, as " + dir.file("rotation.0001.ply") + " states in its header"), std::string::npos)
      << out;
  EXPECT_NE(test::read_file(dir.path() / "stated" / "job.toml").find("\nfps=12\n"), std::string::npos);
  ASSERT_EQ(run_fluidtex(base + "-q -o " + q(dir.file("given")) + " --fps 12", &out), 0) << out;
  EXPECT_EQ(out, "");
  ASSERT_EQ(run_fluidtex(base + "-q -o " + q(dir.file("other")) + " --fps 24", &out), 0) << out;
  EXPECT_NE(out.find("warning: --fps 24 given, but " + dir.file("rotation.0001.ply") + " states 12 fps"),
            std::string::npos)
      << out;
  const std::string stated = test::read_file(dir.path() / "stated" / "atlas.0003.exr");
  EXPECT_FALSE(stated.empty());
  EXPECT_TRUE(stated == test::read_file(dir.path() / "given" / "atlas.0003.exr"));
  EXPECT_FALSE(stated == test::read_file(dir.path() / "other" / "atlas.0003.exr"));
}

/// The numbers of one key in a run's stats.jsonl, by frame.
std::map<int, double> stats_numbers(const fs::path& stats_path, const std::string& key) {
  std::map<int, double> out;
  std::istringstream lines(test::read_file(stats_path));
  for (std::string line; std::getline(lines, line);) {
    const std::size_t at = line.find("\"" + key + "\":");
    if (at == std::string::npos) continue;
    out[std::stoi(line.substr(line.find("\"frame\":") + 8))] = std::stod(line.substr(at + key.size() + 3));
  }
  return out;
}

TEST(Cli, AStepRangeFollowsTheFramesItSkips) {
  // The merge scene makes and retires patches every frame. With 1-7x2 the
  // run reads and tracks frames 2, 4 and 6 without writing them: frames 3, 5
  // and 7 are those of the every-frame run, and their stats and states count
  // every step since the previous written frame.
  test::TempDir dir;
  std::string out;
  ASSERT_EQ(
      run_fluidtex(
          "gen merge -o " + q(dir.str()) + " --frames 7 --resolution 20 --exemplar gravel --exemplar-pixels 32", &out),
      0)
      << out;
  const std::string base =
      "run -q -i " + q(dir.file("merge.####.ply")) + " -e " + q(dir.file("gravel.png")) + " --atlas-size 64 ";
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("every")), &out), 0) << out;
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("step")) + " --frames 1-7x2", &out), 0) << out;
  const fs::path every = dir.path() / "every", step = dir.path() / "step";
  for (const char* f : {"atlas.0003.exr", "mesh.0003.obj", "atlas.0005.exr", "atlas.0007.exr", "mesh.0007.obj"}) {
    const std::string a = test::read_file(every / f);
    EXPECT_FALSE(a.empty()) << f;
    EXPECT_TRUE(a == test::read_file(step / f)) << f;
  }
  for (const char* f : {"atlas.0002.exr", "mesh.0004.obj", "state/patches.0006.bin"})
    EXPECT_FALSE(fs::exists(step / f)) << f;

  const auto created = stats_numbers(every / "stats.jsonl", "patches_created");
  const auto removed = stats_numbers(every / "stats.jsonl", "patches_removed");
  const auto step_created = stats_numbers(step / "stats.jsonl", "patches_created");
  const auto step_removed = stats_numbers(step / "stats.jsonl", "patches_removed");
  EXPECT_EQ(step_created.size(), 4u);
  EXPECT_EQ(stats_numbers(step / "stats.jsonl", "frames_followed"), (std::map<int, double>{{3, 1}, {5, 1}, {7, 1}}));
  int retired_between = 0;
  for (int f : {3, 5, 7}) {
    EXPECT_EQ(step_created.at(f), created.at(f - 1) + created.at(f)) << f;
    EXPECT_EQ(step_removed.at(f), removed.at(f - 1) + removed.at(f)) << f;
    // The state lists the retirements of both steps.
    auto mesh = std::make_shared<const FrameMesh>(read_frame(dir.file("merge.000" + std::to_string(f) + ".ply")));
    const std::string name = "state/patches.000" + std::to_string(f) + ".bin";
    const std::size_t both = Tracker::load((step / name).string(), mesh).retired().size();
    const std::size_t last = Tracker::load((every / name).string(), mesh).retired().size();
    EXPECT_GE(both, last) << f;
    retired_between += static_cast<int>(both - last);
  }
  EXPECT_GT(retired_between, 0);

  // Resumed half-way, the stepped run goes on through the frames it skips.
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("part")) + " --frames 1-3x2", &out), 0) << out;
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("part")) + " --frames 1-7x2 --resume", &out), 0) << out;
  EXPECT_TRUE(test::read_file(every / "atlas.0007.exr") == test::read_file(dir.path() / "part" / "atlas.0007.exr"));

  // --skipped-frames ignore steps across the gap (another texture), and a
  // skipped frame missing on disk is stepped across too.
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("ignore")) + " --frames 1-7x2 --skipped-frames ignore", &out), 0)
      << out;
  EXPECT_FALSE(test::read_file(every / "atlas.0005.exr") == test::read_file(dir.path() / "ignore" / "atlas.0005.exr"));
  EXPECT_TRUE(stats_numbers(dir.path() / "ignore" / "stats.jsonl", "frames_followed").empty());
  // A skipped frame that cannot be read fails the run, naming it and the way round it.
  test::write_file(dir.path() / "merge.0004.ply", "ply\nformat ascii 1.0\nelement vertex 3\n");
  EXPECT_EQ(run_fluidtex(base + "-o " + q(dir.file("bad")) + " --frames 1-7x2", &out), 2);
  EXPECT_NE(out.find("merge.0004.ply: "), std::string::npos) << out;
  EXPECT_NE(out.find("--skipped-frames ignore"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir.path() / "bad" / "atlas.0005.exr"));
  fs::remove(dir.path() / "merge.0004.ply");
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("gap")) + " --frames 1-7x2", &out), 0) << out;
  EXPECT_TRUE(test::read_file(every / "atlas.0003.exr") == test::read_file(dir.path() / "gap" / "atlas.0003.exr"));
  EXPECT_FALSE(test::read_file(every / "atlas.0005.exr") == test::read_file(dir.path() / "gap" / "atlas.0005.exr"));
  EXPECT_EQ(stats_numbers(dir.path() / "gap" / "stats.jsonl", "frames_followed"),
            (std::map<int, double>{{3, 1}, {7, 1}}));
}

TEST(Cli, SameOutputForOneAndTwoThreads) {
  test::TempDir dir;
  std::string out;
  const std::string base = rotation_run(dir, 3, 16, 64, 128);
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("t1")) + " --threads 1", &out), 0) << out;
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("t2")) + " --threads 2", &out), 0) << out;
  for (const char* f : {"atlas.0003.exr", "mesh.0003.obj", "state/patches.0003.bin"}) {
    const std::string a = test::read_file(dir.path() / "t1" / f), b = test::read_file(dir.path() / "t2" / f);
    EXPECT_FALSE(a.empty()) << f;
    EXPECT_TRUE(a == b) << f;
  }
  // Zip, and a lossy, block-parallel EXR compression too.
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("z1")) + " --threads 1 --frames 1 --compression zip", &out), 0);
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("z2")) + " --threads 2 --frames 1 --compression zip", &out), 0);
  EXPECT_TRUE(test::read_file(dir.path() / "z1" / "atlas.0001.exr") ==
              test::read_file(dir.path() / "z2" / "atlas.0001.exr"));
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("d1")) + " --threads 1 --frames 1 --compression dwaa", &out), 0);
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("d2")) + " --threads 2 --frames 1 --compression dwaa", &out), 0);
  EXPECT_TRUE(test::read_file(dir.path() / "d1" / "atlas.0001.exr") ==
              test::read_file(dir.path() / "d2" / "atlas.0001.exr"));
  // A MIP-mapped texture (levels filtered in parallel).
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("m1")) + " --threads 1 --frames 1 --texture-layout mipmap", &out),
            0);
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("m2")) + " --threads 2 --frames 1 --texture-layout mipmap", &out),
            0);
  EXPECT_TRUE(test::read_file(dir.path() / "m1" / "atlas.0001.exr") ==
              test::read_file(dir.path() / "m2" / "atlas.0001.exr"));
}

TEST(Cli, ColourHeightAndNormalAtlasesFromOneRun) {
  test::TempDir dir;
  std::string out;
  const std::string base = rotation_run(dir, 2, 12, 32, 64);
  const std::string maps = " --displacement-atlas " + q(dir.file("o/h/height.####.exr")) + " --normal-atlas " +
                           q(dir.file("o/n/normal.$F4.exr")) + " --bump-height 0.5";
  ASSERT_EQ(run_fluidtex(base + "-o " + q(dir.file("o")) + maps, &out), 0) << out;
  const Image color = read_image(dir.file("o/atlas.0002.exr"));
  const Image height = read_image(dir.file("o/h/height.0002.exr"));
  const Image normal = read_image(dir.file("o/n/normal.0002.exr"));
  ASSERT_EQ(height.channels, 1);
  ASSERT_EQ(normal.channels, 3);
  ASSERT_EQ(height.pixels.size() * 3, color.pixels.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < height.pixels.size(); ++i) {
    const float* c = color.pixel(i);
    worst = std::max(worst, std::abs(height.pixels[i] - (0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2])));
  }
  EXPECT_LT(worst, 2e-3);  // both stored as half
  bool tilted = false;
  for (std::size_t i = 0; i < normal.pixels.size(); i += 3) {
    const Vec3 n(2.0 * normal.pixels[i] - 1.0, 2.0 * normal.pixels[i + 1] - 1.0, 2.0 * normal.pixels[i + 2] - 1.0);
    EXPECT_NEAR(n.norm(), 1.0, 3e-3);
    EXPECT_GT(n.z(), 0.0);
    tilted = tilted || n.z() < 0.99;
  }
  EXPECT_TRUE(tilted);  // the gravel's relief shows
  const std::string mtl = test::read_file(dir.path() / "o" / "mesh.0002.mtl");
  EXPECT_NE(mtl.find("\ndisp h/height.0002.exr\n"), std::string::npos) << mtl;
  EXPECT_NE(mtl.find("\nbump -bm "), std::string::npos) << mtl;
  EXPECT_NE(mtl.find("\nnorm n/normal.0002.exr\n"), std::string::npos) << mtl;
  // Heights and normals are data: EXR only.
  EXPECT_EQ(run_fluidtex(base + "-o " + q(dir.file("p")) + " --normal-atlas " + q(dir.file("p/n.####.png")), &out), 2);
  EXPECT_NE(out.find("--normal-atlas"), std::string::npos) << out;
}

TEST(Cli, CoverageCheckFillsTheHolesThePlainPoissonUpdateLeaves) {
  // The merge outline grows faster than patches follow: the plain Poisson
  // update (--no-coverage-check) leaves bare surface, the default fills it.
  test::TempDir dir;
  std::string out;
  ASSERT_EQ(run_fluidtex("gen merge -o " + q(dir.str()) + " --frames 12 --resolution 32", &out), 0) << out;
  auto worst_uncovered = [&](const std::string& name, const std::string& flags) {
    EXPECT_EQ(run_fluidtex(
                  "run -q --track-only -i " + q(dir.file("merge.####.ply")) + " -o " + q(dir.file(name)) + flags, &out),
              0)
        << out;
    const std::string stats = test::read_file(dir.path() / name / "stats.jsonl");
    double worst = 0.0;
    const std::string key = "\"uncovered_fraction\":";
    for (std::size_t at = stats.find(key); at != std::string::npos; at = stats.find(key, at + 1)) {
      worst = std::max(worst, std::stod(stats.substr(at + key.size())));
    }
    EXPECT_NE(stats.find("\"frame\":12"), std::string::npos);
    return worst;
  };
  EXPECT_EQ(worst_uncovered("checked", ""), 0.0);
  EXPECT_GT(worst_uncovered("plain", " --no-coverage-check"), 1e-3);
}

}  // namespace
}  // namespace fluidtex
