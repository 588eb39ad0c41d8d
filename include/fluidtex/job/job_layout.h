/// @file job_layout.h
/// @brief Where a job's files are under its output folder: the per-frame
/// outputs (atlas, UV mesh and its material, height and normal atlases,
/// AOVs), the states, and the temporaries an interrupted step leaves. The
/// job's other units (the record, the run, synth) ask here.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "fluidtex/job/job_options.h"

namespace fluidtex {

/// A file a job writes per frame, and the option (or what) that names it.
struct FrameOutput {
  std::string pattern;
  std::string what;  ///< "--atlas", "the material of --mesh", "--aov weight", ...
};

/// The files a job writes per frame besides its state: the atlas, the UV
/// mesh (and its material for an OBJ), the height and normal atlases, the AOVs.
std::vector<FrameOutput> labelled_frame_outputs(const JobOptions& options);

/// Their patterns alone.
std::vector<std::string> frame_output_patterns(const JobOptions& options);

/// The material file next to an OBJ pattern (`mesh.####.obj` → `mesh.####.mtl`).
std::string material_pattern(const std::string& obj_pattern);

/// Removes the atlas, AOVs and UV mesh of `frame`, and its debug views with
/// --debug-views (when its state could not be written: a frame is complete
/// with its state, or absent).
void remove_frame_outputs(const JobOptions& options, int frame);

/// The per-frame debug views of a job in `dir` (--debug-views): the patches
/// and the disks, DIR/debug/patches.####.ply and DIR/debug/disks.####.ply.
std::vector<std::string> debug_view_patterns(const std::string& dir);

/// The state files of a job in `dir`: DIR/state/patches.####.bin.
std::string state_pattern(const std::string& dir);

/// The state file of `frame` under `dir`.
std::string state_path(const std::string& dir, int frame);

/// InputError, before anything is written, when two of the job's outputs
/// (atlas, UV mesh and its material, height and normal atlases, AOVs,
/// states) would be the same file, or an output would overwrite an input
/// (the frames, the exemplar): names both.
void check_output_paths(const JobOptions& options);

/// Removes the temporaries a killed run or synth left in the job's output
/// folders (remove_stale_temporaries: this machine's dead writers', and
/// other machines' whose target `owned` accepts). Returns how many.
std::size_t remove_interrupted_temporaries(const JobOptions& options,
                                           const std::function<bool(const std::string&)>& owned);

}  // namespace fluidtex
