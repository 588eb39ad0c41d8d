/// @file pipeline.h
/// @brief `fluidtex run`: the whole job over a sequence, frame by frame.
#pragma once

#include <cstdint>
#include <string>

#include "fluidtex/advection.h"
#include "fluidtex/options.h"
#include "fluidtex/report.h"

namespace fluidtex {

struct OutputOptions {
  std::string dir;                    ///< -o: output folder
  std::string atlas_pattern;          ///< --atlas; empty = DIR/atlas.####.exr
  std::string mesh_pattern;           ///< --mesh; empty = DIR/mesh.####.obj
  bool resume = false;                ///< --resume: continue after the last complete frame
  bool debug_views = false;           ///< --debug-views: patch/disk PLYs per frame
  bool write_state = true;            ///< OUT/state/patches.####.bin after every frame

  /// The effective patterns (defaults filled in); InputError when a given
  /// pattern has no frame token or an unsupported extension.
  std::string atlas() const;
  std::string mesh() const;
};

struct JobOptions {
  InputOptions input;
  TrackingOptions tracking;
  Advection advection = Advection::Heun;  ///< --advection
  OutputOptions output;
  std::string exemplar;   ///< -e: exemplar image
  int threads = 0;        ///< 0 = all cores
  std::uint64_t seed = 1;

  void validate() const;  ///< InputError for any bad option
};

struct JobSummary {
  std::size_t frames = 0;        ///< frames processed by this run
  int resumed_after = -1;        ///< frame whose state the run resumed from, −1 if none
  double seconds = 0.0;
};

/// The state file of `frame` under `dir` (DIR/state/patches.####.bin).
std::string state_path(const std::string& dir, int frame);

/// Runs the job. Throws InputError for bad input (before any output is
/// written when the problem can be seen up front), InternalError otherwise.
JobSummary run_job(const JobOptions& options, Reporter& reporter);

}  // namespace fluidtex
