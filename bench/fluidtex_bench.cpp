// fluidtex_bench: per-stage timings at the paper's Table 2 sizes, run by hand
// (not part of ctest). Scenes are generated in memory; each case tracks a few
// warm-up frames, then times one frame's tracking, atlas and synthesis with
// both synthesis methods, for 1 and 2 threads. Prints a Markdown table for
// docs/performance.md.
//
//   fluidtex_bench [--quick] [--case split|dambreak|drop] [--no-exact] [--threads N]
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <oneapi/tbb/global_control.h>

#include "fluidtex/scenes/exemplar_gen.h"
#include "fluidtex/scenes/scenes.h"
#include "fluidtex/texture/atlas.h"
#include "fluidtex/texture/synthesis.h"
#include "fluidtex/tracking/tracker.h"

using namespace fluidtex;

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

struct Case {
  const char* name;   // as in the paper's Table 2
  const char* scene;  // generator
  int resolution;     // → polygon count
  double radius;      // d (0 = default), chosen for the paper's patch count
  int atlas;          // atlas size
  const char* paper;  // the paper's numbers (20 Xeon cores)
};

double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

void run_case(const Case& c, int warmup, bool exact, int threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  SceneOptions so;
  so.resolution = c.resolution;
  so.frames = 48;
  TrackerSettings ts;
  ts.method.radius = c.radius;
  Tracker tracker(ts);
  StepReport last;
  double track_seconds = 0.0;
  for (int f = 1; f <= warmup; ++f) {
    auto mesh = std::make_shared<FrameMesh>(make_scene_frame(c.scene, 10 + f, so));
    const double t0 = now();
    last = tracker.step(mesh, 10 + f, 1.0 / so.fps);
    track_seconds = now() - t0;
  }
  const Exemplar exemplar(make_exemplar("gravel", 512, 1));
  double t0 = now();
  AtlasOptions ao;
  ao.size = c.atlas;
  const Atlas atlas = build_atlas(*tracker.surface(), ao);
  const TexelMap map = build_texel_map(*tracker.surface(), atlas);
  const double atlas_seconds = now() - t0;
  SynthesisOptions opt;
  const TrackingOptions& o = tracker.settings().method;
  opt.tile_size = o.exemplar_tile_size();
  opt.projection_tolerance = o.mpt();
  t0 = now();
  const SynthesisResult raster = synthesize(*tracker.surface(), atlas, map, tracker.patches(), exemplar, opt);
  const double raster_seconds = now() - t0;
  double exact_seconds = -1.0;
  if (exact) {
    opt.method = SynthesisMethod::Exact;
    t0 = now();
    (void)synthesize(*tracker.surface(), atlas, map, tracker.patches(), exemplar, opt);
    exact_seconds = now() - t0;
  }
  std::string stages;
  for (const auto& [stage, secs] : last.seconds) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s%s %.3f", stages.empty() ? "" : ", ", stage.c_str(), secs);
    stages += buf;
  }
  std::printf(
      "| %s | %d | %zu | %d | %d² | %.3f | %.3f | %.3f | %s | %.3f | %s | %.0f | %s |\n", c.name, threads,
      tracker.mesh()->num_faces(), last.counts.total(), c.atlas, track_seconds, atlas_seconds, raster_seconds,
      exact ? std::to_string(exact_seconds).substr(0, 6).c_str() : "–", track_seconds + atlas_seconds + raster_seconds,
      exact && raster_seconds > 0 ? (std::to_string(exact_seconds / raster_seconds).substr(0, 5) + "×").c_str() : "–",
      peak_rss_mb(), stages.c_str());
  std::printf("<!-- %s: paper %s; uncovered %.2e, packing %.2f -->\n", c.name, c.paper, raster.uncovered_fraction(),
              atlas.packing_efficiency);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, exact = true;
  std::string only;
  std::vector<int> thread_counts = {1, 2};
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick"))
      quick = true;
    else if (!std::strcmp(argv[i], "--no-exact"))
      exact = false;
    else if (!std::strcmp(argv[i], "--case") && i + 1 < argc)
      only = argv[++i];
    else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc && std::atoi(argv[i + 1]) > 0)
      thread_counts = {std::atoi(argv[++i])};
    else {
      std::fprintf(stderr, "usage: fluidtex_bench [--quick] [--no-exact] [--case split|dambreak|drop] [--threads N]\n");
      return 2;
    }
  }
  // Radii chosen so that the patch counts match Table 2's.
  const std::vector<Case> cases = {
      {"split", "split", 90, 0.043, 1024, "6k poly, 584 patches, 1k² atlas: 2.8 s"},
      {"dambreak", "rotation", 68, 0.0171, 6144, "7k poly, 6900 patches, 6k² atlas: 90 s"},
      {"drop", "drop", 100, 0.0, 2048, "50k poly (the paper's Lava: 5700 patches, 6k² atlas: 186 s)"},
  };
  std::printf(
      "| case | threads | polygons | patches | atlas | track s | atlas s | raster s | exact s | total s "
      "(raster) | exact/raster | peak MB | tracking stages (s) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Case& c : cases) {
    if (!only.empty() && only != c.name) continue;
    for (int threads : thread_counts)
      run_case(c, quick ? 3 : 8, exact && !(std::string(c.name) == "dambreak"), threads);
  }
  return 0;
}
