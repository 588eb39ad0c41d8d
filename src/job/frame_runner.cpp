#include "fluidtex/job/frame_runner.h"

namespace fluidtex {

FrameReport frame_report(const char* step, const FrameStats& stats, Clock::time_point started, bool has_patches) {
  FrameReport done;
  done.step = step;
  done.frame = stats.frame;
  done.seconds = seconds_since(started);
  if (has_patches) done.patches = stats.patches.total();
  return done;
}

std::shared_ptr<const FrameMesh> read_frame_mesh(const Sequence& sequence, std::size_t index, FrameStats& stats,
                                                 Reporter& reporter) {
  stats.frame = sequence.frames()[index];
  const ScopedStage stage(stats.seconds, "read");
  CleanReport cleaned;
  auto mesh = std::make_shared<const FrameMesh>(sequence.load(index, &cleaned));
  if (cleaned.changed()) reporter.verbose(sequence.path_of(stats.frame) + ": " + cleaned.summary());
  stats.vertices = mesh->num_vertices();
  stats.faces = mesh->num_faces();
  return mesh;
}

}  // namespace fluidtex
