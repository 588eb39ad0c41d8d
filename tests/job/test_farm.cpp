// Render-farm use (job/job_record.h, job/synth_job.h): one tracking step,
// synthesis of frame ranges in any split and order, byte-identical to one
// run; a job is a contract (--resume and synth refuse a different one);
// stale outputs never survive; farm logs; fewer states.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <regex>
#include <sstream>

#include <OpenImageIO/imageio.h>

#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/job/job_record.h"
#include "fluidtex/job/synth_job.h"
#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/version.h"
#include "test_util.h"

namespace fluidtex {
namespace {

namespace fs = std::filesystem;
using test::run_fluidtex;

std::string q(const std::string& s) { return "'" + s + "'"; }

constexpr int kFrames = 6;

/// The settings of the tests' jobs (a test changes them in place of these).
const std::string kSettings = "--atlas-size 128 --seed 3 ";

/// The rotation scene of kFrames frames in `dir` and the start of a run
/// command over it without the settings and -o.
std::string scene_run(const test::TempDir& dir) {
  test::write_rotation_scene(dir.path(), kFrames, 16);
  return "run -q -i " + q(dir.file("rotation.####.ply")) + " -e " + q(dir.file("ex.png")) + " --aov weight ";
}

/// The same, with the settings.
std::string scene(const test::TempDir& dir) { return scene_run(dir) + kSettings; }

/// The files of every frame that must be identical between two folders.
std::vector<std::string> frame_files(int frames = kFrames) {
  std::vector<std::string> names;
  for (int f = 1; f <= frames; ++f) {
    for (const char* p :
         {"atlas.####.exr", "mesh.####.obj", "mesh.####.mtl", "aov/weight.####.exr", "state/patches.####.bin"})
      names.push_back(FramePattern(p).path(f));
  }
  return names;
}

void expect_same_files(const fs::path& a, const fs::path& b, const std::vector<std::string>& names) {
  for (const std::string& n : names) {
    const std::string x = test::read_file(a / n), y = test::read_file(b / n);
    EXPECT_FALSE(x.empty()) << n;
    EXPECT_TRUE(x == y) << n << " differs between " << a << " and " << b;
  }
}

TEST(Farm, TrackThenSynthInAnySplitEqualsOneRun) {
  test::TempDir dir;
  const std::string run = scene(dir);
  std::string out;
  ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file("full")), &out), 0) << out;
  // Chunks as array tasks would run them: one, two, and three out of order.
  const std::vector<std::pair<std::string, std::vector<std::string>>> splits = {
      {"one", {""}}, {"two", {"1-3", "4-6"}}, {"three", {"5-6", "1-2", "3-4"}}};
  for (const auto& [name, chunks] : splits) {
    SCOPED_TRACE(name);
    ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file(name)) + " --track-only", &out), 0) << out;
    for (const std::string& c : chunks) {
      ASSERT_EQ(run_fluidtex("synth -q -o " + q(dir.file(name)) + (c.empty() ? "" : " --frames " + c), &out), 0) << out;
    }
    expect_same_files(dir.path() / "full", dir.path() / name, frame_files());
    // Each chunk wrote its own stats file, one line per frame.
    for (const std::string& c : chunks) {
      const std::vector<int> frames = c.empty() ? parse_frame_range("1-6") : parse_frame_range(c);
      const std::string stats = test::read_file(synth_stats_path(dir.file(name), frames));
      EXPECT_EQ(std::count(stats.begin(), stats.end(), '\n'), static_cast<long>(frames.size())) << stats;
    }
  }
}

/// The string attributes and the chromaticities of an atlas, as OIIO reads them.
std::map<std::string, std::string> atlas_metadata(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << path;
  std::map<std::string, std::string> out;
  if (!in) return out;
  const OIIO::ImageSpec& spec = in->spec();
  for (const char* name : {"oiio:ColorSpace", "Software", "fluidtex:version", "fluidtex:frame", "fluidtex:settings"})
    out[name] = spec.get_string_attribute(name);
  if (const OIIO::ParamValue* p = spec.find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8))) {
    const float* c = static_cast<const float*>(p->data());
    for (int i = 0; i < 8; ++i) out["chromaticities"] += std::to_string(c[i]).substr(0, 6) + " ";
  }
  return out;
}

TEST(Farm, AtlasesNameTheirColourSpaceBuildFrameAndSettings) {
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
  const std::string reseeded = "run -q -i " + q(dir.file("rotation.####.ply")) + " -e " + q(dir.file("ex.png")) +
                               " --aov weight --atlas-size 128 --seed 4 ";
  ASSERT_EQ(run_fluidtex(reseeded + "-o " + q(dir.file("d")) + " --frames 1-2", &out), 0) << out;
  EXPECT_NE(atlas_metadata(dir.file("d/atlas.0002.exr"))["fluidtex:settings"], settings);
}

/// A value of `ref` that differs from its current one (for the contract test).
std::string other_value(const OptionRef& ref) {
  const std::string name = ref.info.name, now = ref.text();
  if (name == "atlas") return "elsewhere/atlas.####.exr";
  if (name == "mesh") return "elsewhere/mesh.####.ply";
  if (ref.kind == OptionRef::Kind::Flag) return now == "true" ? "false" : "true";
  for (const std::string& c : ref.choices) {
    if (c != now) return c;
  }
  if (ref.automatic) return now == "auto" ? "0.5" : "auto";
  if (std::string(ref.type) == "FLOAT" || std::string(ref.type) == "INT") return now == "7" ? "8" : "7";
  return now + "x";
}

TEST(Farm, ResumeRefusesEveryOptionThatChangesTheOutput) {
  test::TempDir dir;
  JobOptions base;
  base.input.pattern = dir.file("in.####.ply");
  base.output.dir = dir.file("out");
  JobRecord job;
  job.options = base;
  job.version = version_line();
  job.frames = {1, 2, 3, 4};
  JobOptions probe = base;
  // The input and the exemplar are compared by content (the newest state's
  // mesh fingerprint, the exemplar's SHA-1), not by path.
  const std::set<std::string> free = {"output",      "resume", "force",    "keep-state", "threads",
                                      "debug-views", "frames", "exemplar", "input",      "velocity-vdb"};
  int checked = 0;
  const std::vector<OptionRef> table = option_table(probe);
  for (std::size_t i = 0; i < table.size(); ++i) {
    const std::string name = table[i].info.name;
    JobRecord given = job;
    OptionRef ref = option_table(given.options)[i];
    ref.set({other_value(ref)});
    if (free.count(name)) {
      EXPECT_NO_THROW(check_resumable(job, given)) << "--" << name << " " << ref.text();
      continue;
    }
    try {
      check_resumable(job, given);
      ADD_FAILURE() << "--" << name << " changed and was not refused";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), dir.file("out/job.toml"));
      EXPECT_TRUE(std::string(e.what()).find("--" + name + " differs") != std::string::npos) << e.what();
      ++checked;
    }
  }
  EXPECT_GT(checked, 30);
  // A relative and an absolute path to the same input are the same input.
  JobRecord same = job;
  same.options.input.pattern = fs::relative(base.input.pattern).string();
  EXPECT_NO_THROW(check_resumable(job, same));
  // The build, the exemplar's content, and frames that do not continue the job's.
  JobRecord other = job;
  other.version = "fluidtex 0.0.9";
  EXPECT_THROW(check_resumable(job, other), InputError);
  other = job;
  other.exemplar_sha1 = "0123";
  EXPECT_THROW(check_resumable(job, other), InputError);
  for (const char* frames : {"2-4", "1-8x2", "1,3"}) {
    other = job;
    other.frames = parse_frame_range(frames);
    EXPECT_THROW(check_resumable(job, other), InputError) << frames;
  }
  for (const char* frames : {"1-2", "1-12"}) {  // shorter or longer: fine
    other = job;
    other.frames = parse_frame_range(frames);
    EXPECT_NO_THROW(check_resumable(job, other)) << frames;
  }
}

/// The command line `args` is refused: exit 2, one line, naming `named`.
void refused(const std::string& args, const std::string& named) {
  SCOPED_TRACE(args);
  std::string text;
  EXPECT_EQ(run_fluidtex(args, &text), 2) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
  EXPECT_NE(text.find(named), std::string::npos) << text;
}

TEST(Farm, ResumeAndSynthRefuseAnotherJobWithExit2AndOneLine) {
  test::TempDir dir;
  const std::string bare = scene_run(dir), run = bare + kSettings;
  const std::string out_dir = dir.file("job");
  std::string out;
  ASSERT_EQ(run_fluidtex(run + "-o " + q(out_dir) + " --frames 1-3 --track-only", &out), 0) << out;
  // --resume with other settings, or frames that do not continue the job's
  // (the issue's case: --frames 4-6 with states up to 3).
  refused(bare + "-o " + q(out_dir) + " --track-only --resume --seed 3 --atlas-size 256", "--atlas-size differs");
  refused(bare + "-o " + q(out_dir) + " --track-only --resume --seed 4 --atlas-size 128", "--seed differs");
  refused(run + "-o " + q(out_dir) + " --resume", "--track-only differs");
  refused(run + "-o " + q(out_dir) + " --track-only --resume --frames 4-6", "--frames: 4-6 does not continue");
  test::write_rotation_scene(dir.path() / "other", 1, 12, "ex.png", 32, 9);  // another mesh, other pixels
  refused("run -q -i " + q(dir.file("rotation.####.ply")) + " -e " + q(dir.file("other/ex.png")) +
              " --atlas-size 128 --seed 3 --aov weight --track-only --resume -o " + q(out_dir),
          "--exemplar: its content differs");
  // synth: frames outside the job, an exemplar changed since tracking, a
  // state from another input, another build, a missing state.
  refused("synth -o " + q(out_dir) + " --frames 3-4", "frame 4 is not one of the job's frames 1-3");
  const std::string exemplar = test::read_file(dir.path() / "ex.png");
  fs::copy_file(dir.path() / "other" / "ex.png", dir.path() / "ex.png", fs::copy_options::overwrite_existing);
  refused("synth -o " + q(out_dir), "the exemplar changed since the job was tracked");
  test::write_file(dir.path() / "ex.png", exemplar);
  const std::string frame2 = test::read_file(dir.path() / "rotation.0002.ply");
  fs::copy_file(dir.path() / "other" / "rotation.0001.ply", dir.path() / "rotation.0002.ply",
                fs::copy_options::overwrite_existing);
  refused("synth -o " + q(out_dir) + " --frames 2", "does not match frame 2's mesh");
  test::write_file(dir.path() / "rotation.0002.ply", frame2);
  const std::string record = test::read_file(dir.path() / "job" / "job.toml");
  std::string edited = std::regex_replace(record, std::regex("version=\"[^\"]*\""), "version=\"fluidtex 0.0.9\"");
  test::write_file(dir.path() / "job" / "job.toml", edited);
  refused("synth -o " + q(out_dir), "the job was tracked by fluidtex 0.0.9");
  refused(run + "-o " + q(out_dir) + " --track-only --resume", "the job was made by fluidtex 0.0.9");
  test::write_file(dir.path() / "job" / "job.toml", record);
  fs::remove(dir.path() / "job" / "state" / "patches.0002.bin");
  refused("synth -o " + q(out_dir), "patches.0002.bin: missing: frame 2 was not tracked");
  refused("synth -o " + q(dir.file("nowhere")), "job.toml: missing");
  // Nothing was synthesised by any refused step.
  EXPECT_FALSE(fs::exists(dir.path() / "job" / "atlas.0001.exr"));
  // Flow-map jobs and jobs tracked without an exemplar have nothing to synthesise.
  ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file("fm")) + " --frames 1-2 --method flowmap", &out), 0) << out;
  refused("synth -o " + q(dir.file("fm")), "--method flowmap");
  ASSERT_EQ(run_fluidtex("run -q --track-only -i " + q(dir.file("rotation.####.ply")) + " --frames 1-2 -o " +
                             q(dir.file("noex")),
                         &out),
            0)
      << out;
  refused("synth -o " + q(dir.file("noex")), "the job has no exemplar");
}

TEST(Farm, ACacheMountedElsewhereIsFoundWhereAStepIsToldAndCheckedByContent) {
  // The job is tracked with its input and exemplar in a/; on the render
  // node they are in b/ (a/ does not exist there).
  test::TempDir dir;
  test::write_rotation_scene(dir.path() / "a", kFrames, 16);
  test::write_rotation_scene(dir.path() / "other", kFrames, 17, "ex.png", 32, 9);  // another cache and exemplar
  auto in = [&](const std::string& where) {
    return " -i " + q(dir.file(where + "/rotation.####.ply")) + " -e " + q(dir.file(where + "/ex.png")) + " ";
  };
  const std::string settings = " --aov weight " + kSettings;
  std::string out;
  ASSERT_EQ(run_fluidtex("run -q" + in("a") + settings + "-o " + q(dir.file("full")), &out), 0) << out;
  ASSERT_EQ(run_fluidtex("run -q --track-only" + in("a") + settings + "-o " + q(dir.file("job")), &out), 0) << out;
  ASSERT_EQ(run_fluidtex("run -q --track-only --frames 1-3" + in("a") + settings + "-o " + q(dir.file("part")), &out),
            0)
      << out;
  fs::rename(dir.path() / "a", dir.path() / "b");
  // synth: where job.toml says, nothing is found; where it is told, the
  // frames are one run's; another cache or exemplar there is refused.
  refused("synth -o " + q(dir.file("job")), dir.file("a/ex.png"));
  refused("synth -o " + q(dir.file("job")) + " -e " + q(dir.file("b/ex.png")), dir.file("a/rotation.0001.ply"));
  refused("synth -o " + q(dir.file("job")) + in("other"), "the exemplar changed since the job was tracked");
  refused("synth -o " + q(dir.file("job")) + " --frames 2 -i " + q(dir.file("other/rotation.####.ply")) + " -e " +
              q(dir.file("b/ex.png")),
          "does not match frame 2's mesh");
  EXPECT_FALSE(fs::exists(dir.path() / "job" / "atlas.0002.exr"));
  ASSERT_EQ(run_fluidtex("synth -q -o " + q(dir.file("job")) + in("b"), &out), 0) << out;
  expect_same_files(dir.path() / "full", dir.path() / "job", frame_files());
  // --resume continues from the cache where it is now, and records it there;
  // another cache is refused at the newest state.
  refused("run -q --track-only" + in("other") + settings + "--resume -o " + q(dir.file("part")),
          "--exemplar: its content differs");
  refused("run -q --track-only -i " + q(dir.file("other/rotation.####.ply")) + " -e " + q(dir.file("b/ex.png")) +
              settings + "--resume -o " + q(dir.file("part")),
          "does not match frame 3's mesh");
  ASSERT_EQ(run_fluidtex("run -q --track-only" + in("b") + settings + "--resume -o " + q(dir.file("part")), &out), 0)
      << out;
  for (int f = 1; f <= kFrames; ++f) {
    const std::string state = FramePattern("state/patches.####.bin").path(f);
    EXPECT_TRUE(test::read_file(dir.path() / "full" / state) == test::read_file(dir.path() / "part" / state)) << f;
  }
  EXPECT_NE(test::read_file(dir.path() / "part" / "job.toml").find(dir.file("b/rotation.####.ply")), std::string::npos);
  // eval measures against the cache where it is told, and refuses another.
  refused("eval -q -o " + q(dir.file("full")) + " --samples 2000 --flow-width 0", dir.file("a/"));
  refused("eval -q -o " + q(dir.file("full")) + " -i " + q(dir.file("other/rotation.####.ply")) + " -e " +
              q(dir.file("b/ex.png")) + " --samples 2000 --flow-width 0",
          "does not match frame");
  EXPECT_EQ(run_fluidtex("eval -q -o " + q(dir.file("full")) + in("b") + " --samples 2000 --flow-width 0", &out), 0)
      << out;
}

TEST(Farm, ARunNeverLeavesAnotherJobsOutputsBehind) {
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

TEST(Farm, OffATerminalEveryFrameLogsOneLine) {
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

TEST(Farm, PrunedStatesStillResumeAndSynthesise) {
  test::TempDir dir;
  const std::string run = scene(dir);
  std::string out;
  ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file("full")), &out), 0) << out;
  // run --keep-state last: one state at a time, and --resume carries on.
  ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file("last")) + " --frames 1-4 --keep-state last", &out), 0) << out;
  EXPECT_EQ(test::list_dir(dir.path() / "last" / "state"), std::vector<std::string>{"patches.0004.bin"});
  ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file("last")) + " --resume --keep-state last", &out), 0) << out;
  EXPECT_EQ(test::list_dir(dir.path() / "last" / "state"), std::vector<std::string>{"patches.0006.bin"});
  std::vector<std::string> outputs;
  for (const std::string& n : frame_files()) {
    if (!n.starts_with("state/")) outputs.push_back(n);
  }
  expect_same_files(dir.path() / "full", dir.path() / "last", outputs);
  // synth --prune-state: the textured frames' states go, the job's last
  // stays; a re-run (a task killed while pruning) skips them; the job resumes.
  ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file("pruned")) + " --frames 1-4 --track-only", &out), 0) << out;
  ASSERT_EQ(run_fluidtex("synth -q -o " + q(dir.file("pruned")) + " --frames 1-4 --prune-state", &out), 0) << out;
  EXPECT_EQ(test::list_dir(dir.path() / "pruned" / "state"), std::vector<std::string>{"patches.0004.bin"});
  ASSERT_EQ(run_fluidtex("synth -q -o " + q(dir.file("pruned")) + " --frames 1-4 --prune-state", &out), 0) << out;
  EXPECT_EQ(run_fluidtex("synth -q -o " + q(dir.file("pruned")) + " --frames 1-4", &out), 2) << out;
  ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file("pruned")) + " --track-only --resume", &out), 0) << out;
  ASSERT_EQ(run_fluidtex("synth -q -o " + q(dir.file("pruned")) + " --frames 5-6", &out), 0) << out;
  expect_same_files(dir.path() / "full", dir.path() / "pruned", outputs);
  // A tracking step keeps every state.
  EXPECT_EQ(run_fluidtex(run + "-o " + q(dir.file("x")) + " --track-only --keep-state last", &out), 2) << out;
}

TEST(Farm, ASynthStepRemovesOnlyItsOwnFilesTemporaries) {
  test::TempDir dir;
  const std::string run = scene(dir);
  std::string out;
  ASSERT_EQ(run_fluidtex(run + "-o " + q(dir.file("job")) + " --track-only", &out), 0) << out;
  // A task killed on another machine left temporaries for frames 2 and 5.
  const fs::path job = dir.path() / "job";
  test::write_file(job / ".atlas.0002.tmp-999999999-0-deadnode.exr", "half");
  test::write_file(job / ".atlas.0005.tmp-999999999-0-deadnode.exr", "half");
  ASSERT_EQ(run_fluidtex("synth -q -o " + q(job.string()) + " --frames 1-3", &out), 0) << out;
  EXPECT_FALSE(fs::exists(job / ".atlas.0002.tmp-999999999-0-deadnode.exr"));
  EXPECT_TRUE(fs::exists(job / ".atlas.0005.tmp-999999999-0-deadnode.exr"));  // another task's frame
  ASSERT_EQ(run_fluidtex("synth -q -o " + q(job.string()) + " --frames 4-6", &out), 0) << out;
  EXPECT_FALSE(fs::exists(job / ".atlas.0005.tmp-999999999-0-deadnode.exr"));
}

}  // namespace
}  // namespace fluidtex
