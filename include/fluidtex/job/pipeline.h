/// @file pipeline.h
/// @brief `fluidtex run`: the whole job over a sequence, frame by frame.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>

#include <oneapi/tbb/task_group.h>
#include <string>
#include <vector>

#include "fluidtex/io/image_io.h"
#include "fluidtex/io/sequence.h"
#include "fluidtex/io/stats.h"
#include "fluidtex/job/job_layout.h"  // the job's files, which every user of the run names
#include "fluidtex/job/job_options.h"
#include "fluidtex/texture/atlas.h"
#include "fluidtex/texture/flowmap.h"
#include "fluidtex/texture/synthesis.h"
#include "fluidtex/tracking/advection.h"
#include "fluidtex/tracking/options.h"
#include "fluidtex/util/report.h"
#include "fluidtex/util/timing.h"

namespace fluidtex {

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

/// The exemplar as synthesis uses it: read through OpenImageIO, turned to
/// one channel (Rec. 709 luminance) for displacement.
Exemplar load_exemplar(const std::string& path, bool displacement);

/// The synthesis settings of a job: blend, method, and the exemplar scale
/// and projection tolerance that follow from the resolved tracking lengths.
SynthesisOptions synthesis_options(const TrackingOptions& resolved, const SynthesisJobOptions& so);

/// Synthesis of one frame from a tracker's state: atlas, texel map, Eq. 7,
/// then the atlas image (and AOVs) and the UV mesh written atomically.
/// Fills the synthesis numbers and stage seconds of `stats`.
void synthesize_frame(const SurfaceIndex& surface, const std::vector<Patch>& patches, const TrackingOptions& resolved,
                      const Exemplar& exemplar, const JobOptions& options, int frame, FrameStats& stats);

/// The same for the flow-map baseline (flowmap.h): the same atlas, texel
/// map, writers and stats, the texels from the two advected uv sets.
void synthesize_flowmap_frame(const SurfaceIndex& surface, const FlowMapFrame& flow, const Exemplar& exemplar,
                              const JobOptions& options, int frame, FrameStats& stats, double tile_size);

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

/// Runs the job (either method). Throws InputError for bad input (before any output is
/// written when the problem can be seen up front), InternalError otherwise.
JobSummary run_job(const JobOptions& options, Reporter& reporter);

}  // namespace fluidtex
