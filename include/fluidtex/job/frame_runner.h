/// @file frame_runner.h
/// @brief The frame pipeline both `run` and `synth` drive: frames read in
/// order, tracked in order (run), textured in parallel and written in order,
/// a few frames in flight at once (TBB's parallel_pipeline); and what a step
/// reads of a frame and says of it.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>

#include <oneapi/tbb/parallel_pipeline.h>
#include <oneapi/tbb/task_group.h>

#include "fluidtex/geometry/mesh.h"
#include "fluidtex/io/sequence.h"
#include "fluidtex/job/frame_stats.h"
#include "fluidtex/util/report.h"
#include "fluidtex/util/timing.h"

namespace fluidtex {

/// What a step (run, synth) did.
struct JobSummary {
  std::size_t frames = 0;  ///< frames processed by this run
  int resumed_after = -1;  ///< frame whose state the run resumed from, −1 if none
  double seconds = 0.0;
};

/// Reads frame `index` of `sequence`, cleaned (what cleaning did as a
/// verbose message); fills the frame number, "read" seconds, vertex and face
/// counts of `stats`.
std::shared_ptr<const FrameMesh> read_frame_mesh(const Sequence& sequence, std::size_t index, FrameStats& stats,
                                                 Reporter& reporter);

/// What the log says of a finished frame (Reporter::frame_done): `step`, the
/// frame of `stats`, the seconds since `started`, its patches when
/// `has_patches`.
FrameReport frame_report(const char* step, const FrameStats& stats, Clock::time_point started, bool has_patches);

/// Runs `f` (a stage of a frame pipeline) in a TBB context of its own. When
/// one frame fails, TBB cancels the pipeline's context and with it every
/// parallel loop bound to it: a stage still running for another frame would
/// see its loops stop half-way and go on with half-filled results. Isolated,
/// the stage finishes whole (its frame is then dropped); its own exceptions
/// still reach the pipeline.
template <class F>
void isolated_stage(const F& f) {
  tbb::task_group_context context(tbb::task_group_context::isolated);
  tbb::task_group group(context);
  group.run_and_wait(f);
}

/// The stages of a frame pipeline over frames of type `Work`.
template <class Work>
struct FrameStages {
  std::function<std::shared_ptr<Work>()> read;  ///< in frame order; nullptr when no frame is left
  std::function<void(Work&)> track;             ///< in frame order (isolated_stage)
  std::function<void(Work&)> texture;           ///< in parallel (isolated_stage)
  std::function<void(Work&)> write;             ///< in frame order
};

/// Runs every frame `stages.read` gives through track, texture and write.
/// Reading frame t+1, tracking and texturing overlap; tracking and the
/// writes stay in frame order. At most three frames are in flight, so memory
/// does not grow with the sequence. An exception of a stage ends the run and
/// is rethrown.
template <class Work>
void run_frames(const FrameStages<Work>& stages) {
  using Ptr = std::shared_ptr<Work>;
  constexpr std::size_t kFramesInFlight = 3;
  auto read = [&](tbb::flow_control& fc) -> Ptr {
    Ptr work = stages.read();
    if (!work) fc.stop();
    return work;
  };
  auto track = [&](Ptr work) {
    isolated_stage([&] { stages.track(*work); });
    return work;
  };
  auto texture = [&](Ptr work) {
    isolated_stage([&] { stages.texture(*work); });
    return work;
  };
  auto write = [&](const Ptr& work) { stages.write(*work); };
  tbb::parallel_pipeline(kFramesInFlight, tbb::make_filter<void, Ptr>(tbb::filter_mode::serial_in_order, read) &
                                              tbb::make_filter<Ptr, Ptr>(tbb::filter_mode::serial_in_order, track) &
                                              tbb::make_filter<Ptr, Ptr>(tbb::filter_mode::parallel, texture) &
                                              tbb::make_filter<Ptr, void>(tbb::filter_mode::serial_in_order, write));
}

}  // namespace fluidtex
