/// @file motion_metrics.h
/// @brief Whether the texture moves with the liquid, measured between two
/// frames of a finished run: the warping error (colour change along the
/// solver's velocities, against a texture that does not move and against
/// random points) and the optical flow of two renders against the
/// velocities projected to the image.
#pragma once

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "fluidtex/geometry/image.h"
#include "fluidtex/geometry/mesh.h"
#include "fluidtex/inspect/render.h"
#include "fluidtex/inspect/textured_frame.h"
#include "fluidtex/texture/exemplar.h"

namespace fluidtex {

/// `count` area-weighted random points of `mesh` (face, barycentrics); the
/// same for the same seed and salt.
std::vector<std::pair<int, Vec3>> surface_samples(const FrameMesh& mesh, int count, std::uint64_t seed,
                                                  std::uint64_t salt);

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

struct WarpingError {
  double advected = 0.0;  ///< colour at t vs colour at the advected point at t+1
  double fixed = 0.0;     ///< baseline: the same point, not advected (a texture that does not move)
  double random = 0.0;    ///< baseline: a random point of t+1 (no coherence)
  std::size_t samples = 0;
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

/// Renders two frames measured with `view`'s camera (framing both, no
/// shading, so that only the texture moves) and compares their optical flow
/// with the liquid's motion between them (`motion`, from the velocities of
/// `mesh`, the input frame at t) projected to the image, over pixels inside
/// the surface in both renders (2 pixels away from its silhouette).
FlowError flow_against_velocity(const FrameMesh& mesh, const TexturedFrame& at_t, const TexturedFrame& at_next,
                                const LiquidMotion& motion, const RenderOptions& view,
                                double max_motion = kFlowMaxMotionPx);

}  // namespace fluidtex
