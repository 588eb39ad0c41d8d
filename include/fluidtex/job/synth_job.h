/// @file synth_job.h
/// @brief `fluidtex synth`: the atlases and UV meshes of some frames of a
/// tracked job, from its states (a render farm's array tasks).
///
/// Tracking is sequential; texturing frame t needs only frame t's mesh, the
/// exemplar and the patch state. A tracking step (`run --track-only`) writes
/// OUT/job.toml and OUT/state/; any number of synth steps then texture
/// disjoint frame ranges at once, on any machines sharing OUT. Each writes
/// only its frames' files and its own stats file, and track + any split of
/// synth gives files byte-identical to one `fluidtex run`.
#pragma once

#include <string>
#include <vector>

#include "fluidtex/job/frame_runner.h"
#include "fluidtex/util/report.h"
#include "fluidtex/util/shared_options.h"

namespace fluidtex {

struct SynthRequest {
  std::string dir;           ///< -o: the job's output folder (job.toml, state/)
  std::string frames;        ///< --frames: some of the job's frames; empty = all of them
  bool prune_state = false;  ///< --prune-state: drop the states of the textured frames (not the job's last)
  /// Where this machine sees the job's files when not where job.toml
  /// records them (a cache or exemplar mounted elsewhere); empty = as
  /// recorded. Checked by content as the recorded ones are: each state
  /// against its frame's mesh fingerprint, the exemplar's SHA-1.
  std::string input;         ///< -i: the input frame pattern
  std::string velocity_vdb;  ///< --velocity-vdb: the velocity VDB pattern
  std::string exemplar;      ///< -e: the exemplar

  /// Every field as f(OptionInfo, field) (util/options.h).
  template <class Self, class F>
  static void for_each_option(Self& o, F&& f) {
    using namespace shared_options;
    f(required(kOutput, "The job's output folder (with job.toml and state/)"), o.dir);
    f(with_help(kFrames, "Frames to texture, e.g. 7-12 (default: all of the job's)"), o.frames);
    f(with_help(kInput,
                "Where this machine sees the job's input frames, when not at the pattern job.toml records "
                "(checked against each frame's state)"),
      o.input);
    f(with_help(kVelocityVdb,
                "Where this machine sees the job's --velocity-vdb frames, when not where job.toml records them"),
      o.velocity_vdb);
    f(with_help(kExemplar,
                "Where this machine sees the job's exemplar, when not where job.toml records it (checked by "
                "content)"),
      o.exemplar);
    f(OptionInfo{.name = "prune-state",
                 .help = "Remove the textured frames' states once all are written (the job's last state stays, for "
                         "run --resume)"},
      o.prune_state);
  }
};

/// Where a synth of `frames` writes its per-frame stats:
/// DIR/stats/synth.<frames>.jsonl (format_frame_range, ',' as '_').
std::string synth_stats_path(const std::string& dir, const std::vector<int>& frames);

/// Textures the requested frames of the job in `request.dir`. InputError
/// (before any output) when the job cannot be synthesised as recorded: no or
/// an unreadable job.toml, another build, a flow-map job, no exemplar, an
/// exemplar whose content changed (wherever `request.exemplar` says it is),
/// frames outside the job, a frame without a state; a state from another
/// input (mesh fingerprint, wherever `request.input` says it is) when its
/// frame is read. With `prune_state`, the states go once every requested frame is
/// written, and a re-run skips frames whose state is gone but whose atlas
/// and mesh are there (a killed prune).
JobSummary synth_job(const SynthRequest& request, Reporter& reporter);

}  // namespace fluidtex
