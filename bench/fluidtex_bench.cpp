// fluidtex_bench: the whole job (`fluidtex run`) per case, per stage, for 1
// and 2 threads, with peak memory and optionally the flow-map baseline beside
// it. Run by hand (not part of ctest); docs/performance.md's figures come from
// its tables.
//
// Every measured job runs in a child process of its own, so that its CPU
// time and peak resident memory are its own. A generated case writes its
// frames once (fluidtex gen), then runs the job on them; the cache case runs
// on frames given on the command line (skipped when they are absent).
//
//   fluidtex_bench [--case NAME]... [--threads N]... [--compare-flowmap]
//                  [--cache PATTERN] [--cache-frames A-B] [--frames N]
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <oneapi/tbb/global_control.h>
#include <CLI/CLI.hpp>

#include "fluidtex/io/image_io.h"
#include "fluidtex/job/pipeline.h"
#include "fluidtex/scenes/exemplar_gen.h"
#include "fluidtex/scenes/scenes.h"
#include "fluidtex/util/memory.h"
#include "fluidtex/util/timing.h"

using namespace fluidtex;
namespace fs = std::filesystem;

namespace {

struct Case {
  std::string name;
  std::string scene;  // generator; empty: the cache given with --cache
  int resolution = 64;
  double radius = 0.0;  // d; 0: the default (5 % of the first frame's diagonal)
  int atlas = 2048;
  int frames = 12;  // frames run; the first is not averaged
  std::string note;
  bool by_default = true;  // run without --case
};

/// What one job measured.
struct Result {
  bool ok = false;
  std::string error;
  int frames = 0;
  double wall = 0.0, cpu = 0.0, peak_mib = 0.0;  // whole process
  double faces = 0.0, patches = 0.0;             // means over the averaged frames
  std::map<std::string, double> stage;           // mean wall seconds per averaged frame
  std::vector<std::string> order;                // stages in the order they first ran
};

/// The pipeline's stages as the tables group them.
const char* stage_group(const std::string& stage) {
  if (stage == "read") return "read";
  if (stage == "atlas") return "atlas";
  if (stage == "synthesis") return "synthesis";
  if (stage == "write") return "write";
  if (stage == "state_pack" || stage == "state") return "state";
  return "tracking";
}
const std::vector<std::string> kGroups = {"read", "tracking", "state", "atlas", "synthesis", "write"};

/// The numbers of a stats.jsonl line's flat object `key` ({"name":number,...}),
/// or of its number `key`. The file is the job's own output, one object a line,
/// written by to_json_line: keys and numbers only, no nesting inside these.
std::vector<std::pair<std::string, double>> json_object(const std::string& line, const std::string& key) {
  std::vector<std::pair<std::string, double>> out;
  const std::size_t at = line.find("\"" + key + "\":{");
  if (at == std::string::npos) return out;
  std::size_t p = at + key.size() + 4;
  while (p < line.size() && line[p] != '}') {
    const std::size_t q0 = line.find('"', p), q1 = line.find('"', q0 + 1);
    if (q0 == std::string::npos || q1 == std::string::npos) break;
    const std::string name = line.substr(q0 + 1, q1 - q0 - 1);
    char* end = nullptr;
    const double value = std::strtod(line.c_str() + q1 + 2, &end);
    out.emplace_back(name, value);
    p = static_cast<std::size_t>(end - line.c_str());
    if (p < line.size() && line[p] == ',') ++p;
  }
  return out;
}
double json_value(const std::string& line, const std::string& key) {
  const std::size_t at = line.find("\"" + key + "\":");
  return at == std::string::npos ? 0.0 : std::strtod(line.c_str() + at + key.size() + 3, nullptr);
}

/// Per-frame means of the job's stats.jsonl over every frame but the first
/// (which seeds the whole surface and warms the caches).
void read_stats(const std::string& path, Result& r) {
  std::ifstream in(path);
  std::string line;
  int n = 0;
  for (int k = 0; std::getline(in, line); ++k) {
    if (k == 0) continue;
    ++n;
    r.faces += json_value(line, "faces");
    for (const auto& [name, v] : json_object(line, "patches")) r.patches += v;
    for (const auto& [name, v] : json_object(line, "seconds")) {
      if (!r.stage.count(name)) r.order.push_back(name);
      r.stage[name] += v;
    }
  }
  if (n == 0) return;
  r.faces /= n, r.patches /= n;
  for (auto& [name, v] : r.stage) v /= n;
  r.frames = n;
}

std::string serialise(const Result& r) {
  std::ostringstream s;
  s.precision(17);
  s << r.ok << ' ' << r.frames << ' ' << r.wall << ' ' << r.cpu << ' ' << r.peak_mib << ' ' << r.faces << ' '
    << r.patches << ' ' << r.order.size();
  for (const std::string& name : r.order) s << ' ' << name << ' ' << r.stage.at(name);
  s << '\n' << r.error;
  return s.str();
}

Result deserialise(const std::string& text) {
  Result r;
  std::istringstream s(text);
  std::size_t stages = 0;
  s >> r.ok >> r.frames >> r.wall >> r.cpu >> r.peak_mib >> r.faces >> r.patches >> stages;
  for (std::size_t k = 0; k < stages; ++k) {
    std::string name;
    double v = 0;
    s >> name >> v;
    r.order.push_back(name), r.stage[name] = v;
  }
  s.ignore(1);
  std::getline(s, r.error);
  if (!s && text.empty()) r.error = "the child process died";
  return r;
}

/// Runs `f` in a child process; returns what it wrote (its Result).
template <class F>
std::string in_child(F&& f) {
  int fd[2];
  if (pipe(fd) != 0) return {};
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    const std::string text = f();
    std::size_t done = 0;
    while (done < text.size()) {
      const ssize_t w = write(fd[1], text.data() + done, text.size() - done);
      if (w <= 0) break;
      done += static_cast<std::size_t>(w);
    }
    close(fd[1]);
    _exit(0);
  }
  close(fd[1]);
  std::string text;
  char buf[4096];
  for (ssize_t n; (n = read(fd[0], buf, sizeof buf)) > 0;) text.append(buf, static_cast<std::size_t>(n));
  close(fd[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  return text;
}

/// One job in this (child) process.
Result run_one(const Case& c, const std::string& pattern, const std::string& frames, const std::string& exemplar,
               const std::string& out, TexturingMethod method, int threads) {
  Result r;
  JobOptions o;
  o.input.pattern = pattern;
  o.input.frames = frames;
  o.output.dir = out;
  o.output.force = true;
  o.exemplar = exemplar;
  o.threads = threads;
  o.method = method;
  o.synthesis.atlas.size = c.atlas;
  if (c.radius > 0.0) o.tracking.radius = c.radius;
  // As `fluidtex run --threads N` does.
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  limit_image_io_threads(threads);
  const Clock::time_point start = Clock::now();
  try {
    o.validate();
    run_job(o, silent_reporter());
  } catch (const std::exception& e) {
    r.error = e.what();
    return r;
  }
  r.wall = seconds_since(start);
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  r.cpu = static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
          1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
  r.peak_mib = static_cast<double>(u.ru_maxrss) / 1024.0;
  read_stats(out + "/stats.jsonl", r);
  r.ok = r.frames > 0;
  if (!r.ok) r.error = "no frames in " + out + "/stats.jsonl";
  return r;
}

std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  keep_freed_memory_for_reuse();  // as the command line does
  // The paper's Table 2 sizes (radii chosen so that the patch counts match),
  // the 555k-face drop, and a real cache.
  std::vector<Case> cases = {
      {"split", "split", 90, 0.043, 1024, 12, "paper: 6k poly, 584 patches, 1k² atlas, 2.8 s a frame"},
      {"dambreak", "rotation", 68, 0.0171, 6144, 6, "paper: 7k poly, 6900 patches, 6k² atlas, 90 s a frame"},
      {"drop", "drop", 100, 0.0, 2048, 12, "50k poly"},
      {"large", "drop", 320, 0.0, 4096, 4, "555k poly, 4k² atlas", false},
      {"cache", "", 0, 0.0, 2048, 0, "the frames given with --cache"},
  };
  std::vector<std::string> only;
  std::vector<int> thread_counts = {1, 2};
  bool flowmap = false;
  std::string cache, cache_frames = "1-24", keep;
  int frames = 0;
  CLI::App app{"fluidtex_bench: the whole job per stage, 1 and 2 threads, peak memory (not part of ctest)"};
  app.add_option("--case", only, "Cases to run (default: split dambreak drop cache)")
      ->check(CLI::IsMember({"split", "dambreak", "drop", "large", "cache"}));
  app.add_option("--threads", thread_counts, "Thread counts (default: 1 2)")->check(CLI::PositiveNumber);
  app.add_flag("--compare-flowmap", flowmap, "Also run --method flowmap on the same frames and atlas size");
  app.add_option("--cache", cache, "Frame pattern of a real cache for the cache case (skipped when absent)");
  app.add_option("--cache-frames", cache_frames, "Frames of the cache case (default 1-24)");
  app.add_option("--frames", frames, "Frames per generated case (default: per case, 4 to 12)")
      ->check(CLI::Range(2, 1000));
  app.add_option("--keep", keep, "Keep the generated frames and job outputs in this folder");
  CLI11_PARSE(app, argc, argv);

  const fs::path root =
      keep.empty() ? fs::temp_directory_path() / ("fluidtex_bench." + std::to_string(getpid())) : fs::path(keep);
  fs::create_directories(root);
  const std::string exemplar = (root / "gravel.png").string();
  in_child([&] {
    write_image(exemplar, make_exemplar("gravel", 512, 1));
    return std::string();
  });

  struct Row {
    std::string name, method;
    int threads, atlas;
    Result r;
  };
  std::vector<Row> rows;
  std::vector<std::string> notes;
  for (const Case& c : cases) {
    const bool chosen = only.empty() ? c.by_default : std::count(only.begin(), only.end(), c.name) > 0;
    if (!chosen) continue;
    std::string pattern, range;
    if (c.scene.empty()) {
      if (cache.empty()) {
        notes.push_back("cache: skipped (no --cache given)");
        continue;
      }
      pattern = cache, range = cache_frames;
    } else {
      const int n = frames > 0 ? frames : c.frames;
      const std::string dir = (root / ("scene-" + c.name)).string();
      pattern = in_child([&] {
        SceneOptions so;
        so.resolution = c.resolution;
        so.frames = n + 10;
        return write_scene(c.scene, dir, so);
      });
      range = "11-" + std::to_string(10 + n);  // past the scene's first, calm frames
    }
    const std::vector<TexturingMethod> methods = flowmap
                                                     ? std::vector{TexturingMethod::Patches, TexturingMethod::FlowMap}
                                                     : std::vector{TexturingMethod::Patches};
    for (int threads : thread_counts) {
      for (TexturingMethod m : methods) {
        const std::string method = m == TexturingMethod::Patches ? "patches" : "flowmap";
        const std::string out = (root / (c.name + "-" + method + "-t" + std::to_string(threads))).string();
        const Result r =
            deserialise(in_child([&] { return serialise(run_one(c, pattern, range, exemplar, out, m, threads)); }));
        if (keep.empty()) fs::remove_all(out);  // a 6144² job writes gigabytes
        if (!r.ok) {
          notes.push_back(c.name + " " + method + " " + std::to_string(threads) + " threads: " + r.error);
          if (c.scene.empty()) break;
          continue;
        }
        rows.push_back({c.name, method, threads, c.atlas, r});
        std::fprintf(stderr, "%s %s %d threads: %.2f s a frame\n", c.name.c_str(), method.c_str(), threads,
                     r.wall / (r.frames + 1));
      }
    }
    notes.push_back(c.name + ": " + c.note + (c.scene.empty() ? " (" + pattern + ", " + range + ")" : ""));
  }

  // Whole job: wall and CPU per frame (whole process over every frame),
  // peak memory; with the flow map, the patches' CPU over the flow map's.
  std::printf(
      "| case | method | threads | faces | patches | atlas | frames | wall s / frame | speed-up vs 1 thread | "
      "CPU s / frame |%s peak MiB |\n",
      flowmap ? " CPU vs flow map |" : "");
  std::printf("|---|---|---|---|---|---|---|---|---|---|%s---|\n", flowmap ? "---|" : "");
  auto per_frame = [](const Result& r, double v) { return v / (r.frames + 1); };
  for (const Row& row : rows) {
    std::string ratio;
    if (flowmap) {
      ratio = " – |";
      for (const Row& other : rows) {
        if (row.method == "patches" && other.method == "flowmap" && other.name == row.name &&
            other.threads == row.threads)
          ratio = " " + fixed(row.r.cpu / other.r.cpu, 2) + "× |";
      }
    }
    std::string speedup = "–";
    for (const Row& other : rows) {
      if (row.threads > 1 && other.name == row.name && other.method == row.method && other.threads == 1)
        speedup = fixed(other.r.wall / row.r.wall, 2) + "×";
    }
    std::printf("| %s | %s | %d | %.0f | %s | %d² | %d | %s | %s | %s |%s %.0f |\n", row.name.c_str(),
                row.method.c_str(), row.threads, row.r.faces,
                row.method == "patches" ? fixed(row.r.patches, 0).c_str() : "–", row.atlas, row.r.frames + 1,
                fixed(per_frame(row.r, row.r.wall), 2).c_str(), speedup.c_str(),
                fixed(per_frame(row.r, row.r.cpu), 2).c_str(), ratio.c_str(), row.r.peak_mib);
  }
  // Per stage: mean wall seconds per frame (every frame but the first), the
  // stages grouped. With more than one thread the pipeline runs stages of
  // consecutive frames at once, so a stage's wall time then includes the
  // cores it shared: the whole job's speed-up (above) is the one to read.
  std::printf("\n| case | method | threads |");
  for (const std::string& g : kGroups) std::printf(" %s |", g.c_str());
  std::printf(" stages |\n|---|---|---|");
  for (std::size_t k = 0; k < kGroups.size(); ++k) std::printf("---|");
  std::printf("---|\n");
  auto group_seconds = [](const Result& r, const std::string& g) {
    double s = 0.0;
    for (const auto& [name, v] : r.stage) {
      if (stage_group(name) == g) s += v;
    }
    return s;
  };
  for (const Row& row : rows) {
    std::printf("| %s | %s | %d |", row.name.c_str(), row.method.c_str(), row.threads);
    for (const std::string& g : kGroups) {
      const double s = group_seconds(row.r, g);
      std::printf(" %s |", s > 0.0 ? fixed(s, 3).c_str() : "–");
    }
    std::string stages;
    for (const std::string& name : row.r.order) {
      stages += (stages.empty() ? "" : ", ") + name + " " + fixed(row.r.stage.at(name), 3);
    }
    std::printf(" %s |\n", stages.c_str());
  }
  for (const std::string& n : notes) std::printf("\n- %s", n.c_str());
  std::printf("\n");
  if (keep.empty()) fs::remove_all(root);
  return 0;
}
