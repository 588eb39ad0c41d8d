/// @file compare.h
/// @brief `fluidtex compare GOLDEN NEW`: two runs of the same input compared
/// where the texture is seen, on the surface, so that a different atlas
/// layout (packing, size, gutter) is not a difference.
///
/// Per frame, points are drawn on the golden run's surface (its UV mesh,
/// area-weighted, fixed seed); each run's colour at a point is its atlas,
/// bilinearly, at the uv of the closest point of its own UV mesh. The
/// difference of a point is the mean absolute difference over the channels
/// (linear values, as the atlases store them). A frame passes when the mean
/// difference and the chosen percentile of the differences are within their
/// tolerances, and, where the two frames share their layout (the same atlas
/// size and UV mesh: the same job, on any thread count or machine), when no
/// chart texel differs by more than the per-texel tolerance in any channel:
/// sampled statistics miss damage to a few texels.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fluidtex/geometry/mesh.h"
#include "fluidtex/util/report.h"
#include "fluidtex/util/shared_options.h"

namespace fluidtex {

struct CompareOptions {
  std::string golden;                 ///< the reference run's output folder (with job.toml)
  std::string candidate;              ///< the run to check
  int samples = 50000;                ///< surface points per frame
  std::uint64_t seed = 1;             ///< of the points
  double mean_tolerance = 0.01;       ///< largest mean difference per frame
  double percentile = 99.0;           ///< which percentile of the differences is bounded
  double percentile_tolerance = 0.1;  ///< its largest value per frame
  double max_tolerance = 0.05;        ///< largest difference of one chart texel (same layout)

  /// The options of `compare` as f(OptionInfo, field) (util/options.h).
  template <class Self, class F>
  static void for_each_option(Self& o, F&& f) {
    using namespace shared_options;
    f(OptionInfo{.name = "golden", .help = "The reference run's output folder", .positional = true, .required = true},
      o.golden);
    f(OptionInfo{.name = "new", .help = "The run to check", .positional = true, .required = true}, o.candidate);
    f(with_help(kSamples, "Surface points per frame"), o.samples);
    f(with_help(kSeed, "Seed of the surface points"), o.seed);
    f(OptionInfo{.name = "mean-tolerance",
                 .help = "Largest mean colour difference per frame (linear, mean over channels)",
                 .bounds = between(0.0, 1e9)},
      o.mean_tolerance);
    f(OptionInfo{.name = "percentile",
                 .help = "Which percentile of the differences to bound",
                 .bounds = between(0.0, 100.0)},
      o.percentile);
    f(OptionInfo{.name = "percentile-tolerance",
                 .help = "Largest value of that percentile per frame",
                 .bounds = between(0.0, 1e9)},
      o.percentile_tolerance);
    f(OptionInfo{.name = "max-tolerance",
                 .help = "Largest difference of one chart texel in any channel, checked texel by texel where the "
                         "two runs share their atlas layout (the same job anywhere)",
                 .bounds = between(0.0, 1e9)},
      o.max_tolerance);
  }
};

struct FrameComparison {
  int frame = 0;
  std::size_t samples = 0;
  double mean = 0.0;        ///< mean difference
  double percentile = 0.0;  ///< options.percentile-th percentile of the differences
  double max = 0.0;
  /// Texel by texel (the same layout only; otherwise `texels` is 0): the
  /// chart texels compared, the largest difference in any channel and where.
  std::size_t texels = 0;
  double texel_max = 0.0;
  int worst_udim = 0;               ///< the worst texel's UDIM tile (0: the atlas is one image)
  int worst_x = 0, worst_y = 0;     ///< the worst texel (x right, y down)
  Vec3 worst_point = Vec3::Zero();  ///< where it lies on the surface
  bool passed = true;
};

struct Comparison {
  std::vector<FrameComparison> frames;
  bool passed = true;  ///< every frame passed
};

/// Compares every frame of the golden run with the same frame of the
/// candidate. InputError (exit 2) when a folder has no job.toml, the two jobs
/// cover different frames, a mesh is not OBJ, a frame's atlas or mesh is
/// missing or unreadable, or the atlases have different channel counts.
Comparison compare_runs(const CompareOptions& options, Reporter& reporter);

/// The verdict line: "same: 0 of N frames differ (...)" or "differs: K of N ...".
std::string comparison_verdict(const Comparison& comparison, const CompareOptions& options);

/// The per-frame table (Markdown), the worst texel of each frame that fails
/// texel by texel, then the verdict line.
std::string format_comparison(const Comparison& comparison, const CompareOptions& options);

}  // namespace fluidtex
