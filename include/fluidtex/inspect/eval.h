/// @file eval.h
/// @brief `fluidtex eval`: how good a finished run is, measured per frame
/// from its outputs (atlas + UV mesh), its patch states and the input
/// sequence: coverage, ghosting, patch life, distortion, texture–flow
/// agreement (warping error and optical flow against the fluid velocity),
/// contrast and spectrum. Writes OUT/eval/metrics.jsonl, summary.json, the
/// verdict (verdict.json, verdict.h) and a self-contained report.html.
///
/// The metric functions are exposed on their own so that each can be tested
/// on a case with a known answer.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fluidtex/geometry/mesh.h"
#include "fluidtex/geometry/uv_mesh.h"
#include "fluidtex/inspect/render.h"
#include "fluidtex/inspect/verdict.h"
#include "fluidtex/io/image_io.h"
#include "fluidtex/job/job_options.h"
#include "fluidtex/texture/exemplar.h"
#include "fluidtex/tracking/options.h"
#include "fluidtex/util/report.h"
#include "fluidtex/util/shared_options.h"

namespace fluidtex {

/// Texels of a `size`² atlas covered by the uv triangles of `mesh` (texel
/// centre inside a uv triangle): the chart texels.
std::vector<char> chart_mask(const UVMesh& mesh, int size);

/// σ of each channel of `image` over the texels where `mask` is set,
/// divided by the exemplar's σ (1 = contrast kept; linear blending of k
/// uncorrelated patches gives about 1/sqrt(k)).
std::vector<double> contrast_ratio(const Image& image, const std::vector<char>& mask, const Exemplar& exemplar);

/// Radially averaged log power spectrum (luminance, Hann window, DC left
/// out) of the n×n crop of `image` at (x0, y0); n a power of two. Bin k
/// averages the frequencies with k <= |f| < k+1, k = 1 .. n/2 − 1.
std::vector<double> radial_log_spectrum(const Image& image, int x0, int y0, int n);

/// RMS difference of two radial log spectra (natural log units).
double spectrum_distance(const std::vector<double>& a, const std::vector<double>& b);

/// The exemplar resampled (bilinear, tiled) at `scale` exemplar texels per
/// output texel, an n×n crop starting at exemplar texel (x0, y0).
Image exemplar_crop(const Exemplar& exemplar, double x0, double y0, double scale, int n);

/// A textured surface at one frame: the UV mesh, its atlas and a closest
/// point index over the mesh.
struct TexturedFrame {
  UVMesh mesh;
  Image atlas;
  std::unique_ptr<const FrameMesh> geometry;  ///< mesh positions/triangles (what `surface` indexes)
  std::unique_ptr<SurfaceIndex> surface;

  TexturedFrame(UVMesh m, Image a);
  /// Colour of the surface point nearest to `p` (atlas lookup at its uv).
  void color_at(const Vec3& p, float* out) const;
};

/// `count` area-weighted random points of `mesh` (face, barycentrics); the
/// same for the same seed and salt.
std::vector<std::pair<int, Vec3>> surface_samples(const FrameMesh& mesh, int count, std::uint64_t seed,
                                                  std::uint64_t salt);

/// The most channels an atlas may have for TexturedFrame::color_at's callers
/// (RGBA; fluidtex writes 1, 3 or 4).
constexpr int kMaxLookupChannels = 4;

/// Frame `frame` of a finished run: its atlas and its UV mesh (OBJ) from the
/// run's patterns; InputError naming the file when one is missing or the
/// atlas has more than kMaxLookupChannels channels.
TexturedFrame read_run_frame(const std::string& atlas_pattern, const std::string& mesh_pattern, int frame);

struct WarpingError {
  double advected = 0.0;  ///< colour at t vs colour at the advected point at t+1
  double fixed = 0.0;     ///< baseline: the same point, not advected (a texture that does not move)
  double random = 0.0;    ///< baseline: a random point of t+1 (no coherence)
  std::size_t samples = 0;
};

/// Where the liquid carries a point of frame t by the next frame measured:
/// p + v·dt (the solver's own step) with t's velocity, then one such step
/// with the velocities of each frame in between (the frames a stepped run,
/// 1-120x2, writes nothing for), each read at the surface point nearest the
/// carried one. Between consecutive frames: p + v·dt.
class LiquidMotion {
 public:
  explicit LiquidMotion(double dt) : dt_(dt) {}
  /// A further step with `mesh`'s velocities over `dt` seconds.
  void add_step(std::shared_ptr<const FrameMesh> mesh, double dt);
  /// `p`, whose velocity on frame t is `v`, carried to the next frame measured.
  Vec3 carry(const Vec3& p, const Vec3& v) const;

 private:
  struct Step;
  double dt_;
  std::vector<std::shared_ptr<const Step>> steps_;
};

/// Texture–flow agreement between two frames measured: `samples` points of
/// `mesh` (frame t, with velocities; area-weighted, fixed seed) coloured from
/// frame t, then looked up in the next at motion.carry(p, v) (and at the two
/// baselines). Mean absolute colour difference over channels, divided by
/// the mean σ of the exemplar channels.
WarpingError warping_error(const FrameMesh& mesh, const TexturedFrame& at_t, const TexturedFrame& at_next,
                           const LiquidMotion& motion, const Exemplar& exemplar, int samples, std::uint64_t seed);

struct FlowError {
  double endpoint = 0.0;  ///< mean |flow − projected velocity|, pixels
  double angular = 0.0;   ///< mean angle between (u, v, 1) vectors, degrees
  double speed = 0.0;     ///< mean |projected velocity|, pixels: the endpoint error of a texture that does not move
  std::size_t pixels = 0;
  /// The same means over the pixels whose projected motion is below the
  /// limit (optical flow is unreliable beyond; see optical_flow_error).
  double slow_endpoint = 0.0;
  double slow_speed = 0.0;
  std::size_t slow_pixels = 0;
};

/// Projected motion (pixels per frame) from which the optical flow is not
/// trusted: Farnebäck's window (15 px) no longer holds the displacement.
constexpr double kFlowMaxMotionPx = 15.0;

/// Dense optical flow (OpenCV Farnebäck) from `a` to `b` (linear RGB or
/// grey renders of consecutive frames) compared with `expected` (per pixel,
/// two channels: the image-space displacement in pixels) where `mask` is set;
/// the slow_ means also only where |expected| < `max_motion`.
FlowError optical_flow_error(const Image& a, const Image& b, const Image& expected, const std::vector<char>& mask,
                             double max_motion = kFlowMaxMotionPx);

struct EvalOptions {
  std::string run_dir;   ///< -o: the finished run's folder
  InputOptions input;    ///< -i: the input sequence the run used
  std::string exemplar;  ///< -e; empty = the run's (from OUT/job.toml)
  int samples = 20000;   ///< warping-error sample points per frame pair
  std::uint64_t seed = 1;
  int flow_width = 512;                       ///< render width for the optical-flow metric (0 = off)
  double flow_max_motion = kFlowMaxMotionPx;  ///< pixels per frame; faster pixels are left out of the slow_ flow means
  int report_images = 4;                      ///< preview images in the report
  RenderOptions render;                       ///< camera of the flow renders and report images
  EvalThresholds thresholds;                  ///< the verdict's good / warn / bad bounds

  /// The options of `eval` as f(OptionInfo, field) (util/options.h); the
  /// thresholds have their own table (EvalThresholds).
  template <class Self, class F>
  static void for_each_option(Self& o, F&& f) {
    using namespace shared_options;
    f(with_help(kInput, "The input sequence (default: the run's, from job.toml)"), o.input.pattern);
    f(required(kOutput, "The run's output folder (with job.toml)"), o.run_dir);
    f(with_help(kFrames, "Frames to evaluate (default: the run's)"), o.input.frames);
    f(with_help(kExemplar, "Exemplar (default: the run's, from job.toml)"), o.exemplar);
    f(with_help(kSamples, "Warping-error sample points per frame pair"), o.samples);
    f(with_help(kSeed, "Seed of the sample points"), o.seed);
    f(OptionInfo{.name = "flow-width",
                 .help = "Render width for the optical-flow metric (0: skip it)",
                 .bounds = between(0, 8192)},
      o.flow_width);
    f(OptionInfo{.name = "flow-max-motion",
                 .help = "Projected motion (pixels per frame of the flow renders) from which a pixel is left out of "
                         "the flow_slow_ figures: the optical flow is unreliable beyond",
                 .bounds = between(1e-9, 1e9)},
      o.flow_max_motion);
    f(OptionInfo{.name = "images", .help = "Preview images in the report", .bounds = between(0, 1000)},
      o.report_images);
    f(with_help(kView, "Orthographic view of the renders: top, front, side"), o.render.view);
  }
};

struct EvalSummary {
  std::size_t frames = 0;
  std::string report;  ///< path of report.html
  Verdict verdict;     ///< also in OUT/eval/verdict.json and at the top of the report
};

/// Evaluates the run in options.run_dir made with `job` (read from its
/// job.toml by the caller). InputError for missing or unreadable outputs.
EvalSummary run_eval(const EvalOptions& options, const JobOptions& job, Reporter& reporter);

}  // namespace fluidtex
