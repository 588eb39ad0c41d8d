// A job is a contract (job/job_record.h): --resume and synth refuse a job
// whose options, version or exemplar differ, in one line with exit 2, and
// find a cache mounted elsewhere by its content; a moved output folder is
// read where it is now.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <regex>
#include <string>

#include "farm_fixtures.h"
#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/job/job_record.h"
#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/version.h"
#include "test_util.h"

namespace fluidtex {
namespace {

namespace fs = std::filesystem;
using namespace test::farm;
using test::run_fluidtex;

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

TEST(JobRecord, ResumeRefusesEveryOptionThatChangesTheOutput) {
  test::TempDir dir;
  JobOptions base;
  base.input.pattern = dir.file("in.####.ply");
  base.output.dir = dir.file("out");
  JobRecord job;
  job.options = base;
  job.version = version_line();
  job.frames = {1, 2, 3, 4};
  JobOptions probe = base;
  // The input, the exemplar and the OpenColorIO config are compared by
  // content (the newest state's mesh fingerprint, the files' SHA-1), not by
  // path.
  const std::set<std::string> free = {"output", "resume",   "force", "keep-state",   "threads",    "debug-views",
                                      "frames", "exemplar", "input", "velocity-vdb", "ocio-config"};
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

TEST(JobRecord, ResumeAndSynthRefuseAnotherJobWithExit2AndOneLine) {
  test::TempDir dir;
  const std::string bare = scene_run(dir), run = bare + kSettings;
  const std::string out_dir = dir.file("job");
  std::string out;
  ASSERT_EQ(run_fluidtex(run + "-o " + q(out_dir) + " --frames 1-3 --track-only", &out), 0) << out;
  // --resume with other settings, or frames that do not continue the job's
  // (the case: --frames 4-6 with states up to 3).
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

TEST(JobRecord, TheExemplarSizeReadsBackAndABadOneIsNamed) {
  test::TempDir dir;
  JobOptions o;
  o.output.dir = dir.str();
  JobRecord record = make_job_record(o, {1, 2});
  record.exemplar_size = 0.25;
  test::write_file(dir.path() / "job.toml", job_record_toml(record));
  EXPECT_EQ(read_job_record(dir.str()).exemplar_size, 0.25);
  for (const char* bad : {"\"-1\"", "\"abc\"", "\"nan\""}) {
    test::write_file(dir.path() / "job.toml",
                     job_record_toml(make_job_record(o, {1, 2})) + "exemplar-size=" + bad + "\n");
    try {
      read_job_record(dir.str());
      ADD_FAILURE() << bad << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("[job] exemplar-size: '"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("' is not a length > 0"), std::string::npos) << e.what();
    }
  }
}

TEST(JobRecord, AMovedOutputFolderIsReadWhereItIsNow) {
  // Patterns given inside the output folder are recorded as absolute paths:
  // read from a copy of the folder, they are taken in the copy (compare
  // would otherwise compare the original with itself); one outside stays.
  test::TempDir dir;
  const std::string run = scene(dir) + "--frames 1-2 -o " + q(dir.file("out")) + " --atlas " +
                          q(dir.file("out/tex/atlas.####.exr")) + " --mesh " + q(dir.file("meshes/m.####.obj"));
  std::string out;
  ASSERT_EQ(run_fluidtex(run, &out), 0) << out;
  test::TempDir elsewhere;
  fs::copy(dir.path() / "out", elsewhere.path() / "copy", fs::copy_options::recursive);
  const JobOptions moved = read_job_manifest(elsewhere.file("copy"));
  EXPECT_EQ(moved.output.atlas(), elsewhere.file("copy/tex/atlas.####.exr"));
  EXPECT_EQ(moved.output.mesh(), dir.file("meshes/m.####.obj"));
  EXPECT_EQ(read_job_manifest(dir.file("out")).output.atlas(), dir.file("out/tex/atlas.####.exr"));
  EXPECT_EQ(run_fluidtex("compare " + q(dir.file("out")) + " " + q(elsewhere.file("copy")), &out), 0) << out;
  // Damage in the copy is the copy's.
  const fs::path atlas = elsewhere.path() / "copy/tex/atlas.0002.exr";
  test::write_file(atlas, test::read_file(dir.path() / "out/tex/atlas.0001.exr"));
  EXPECT_EQ(run_fluidtex("compare " + q(dir.file("out")) + " " + q(elsewhere.file("copy")), &out), 1) << out;
}

TEST(JobRecord, ACacheMountedElsewhereIsFoundWhereAStepIsToldAndCheckedByContent) {
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

}  // namespace
}  // namespace fluidtex
