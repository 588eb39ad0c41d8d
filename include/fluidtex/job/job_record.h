/// @file job_record.h
/// @brief OUT/job.toml as a contract, and the files a job owns in OUT.
///
/// job.toml holds every option of the job (job_toml), then a `[job]` table:
/// the build that made it (`version`), the exemplar's content hash
/// (`exemplar-sha1`, what `sha1sum` prints) and the frames it covers
/// (`frames`, resolved). `run --resume` and `fluidtex synth` continue a job
/// only when everything that changes its outputs is the same; anything else
/// is an InputError naming the option (exit 2), never a silent wrong result.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "fluidtex/job/job_options.h"
#include "fluidtex/tracking/tracker.h"

namespace fluidtex {

struct JobRecord {
  JobOptions options;
  std::string version;        ///< version_line() of the build that wrote it; empty: written before records
  std::string exemplar_sha1;  ///< SHA-1 of the exemplar's bytes; empty when the job has no exemplar
  /// SHA-1 of the OpenColorIO config a managed job reads (--ocio-config or
  /// $OCIO); empty when colour is not managed or the config is built in.
  std::string ocio_sha1;
  std::vector<int> frames;  ///< the frames the job covers, ascending
  /// Scene units one exemplar tile spans on the surface (exemplar_span in
  /// frame_texturing.h), whatever --exemplar-size said; unset for a job
  /// without an exemplar. Not part of the contract: it follows from it.
  std::optional<double> exemplar_size;
};

/// SHA-1 of the bytes of `path`, lower-case hex (what `sha1sum` prints);
/// InputError naming the file (as `what`) when it is not a readable regular
/// file.
std::string file_sha1(const std::string& path, const std::string& what = "file");

/// A SHA-1 (hex) of what makes a job's outputs what they are: the build
/// (`version`), the exemplar's content and every option in the contract
/// except the paths (input, output, atlas and mesh patterns) and
/// --track-only, so the same job run in another folder or on another
/// machine, or tracked and then synthesised, has the same hash.
/// Stamped in the atlases (`fluidtex:settings`).
std::string settings_hash(const JobRecord& record);

/// The record a run of `options` over `frames` writes: the exemplar hashed,
/// paths made absolute (a synth step may start in another folder), --resume
/// and --force reset (job.toml used as a --config never resumes or deletes).
JobRecord make_job_record(const JobOptions& options, const std::vector<int>& frames);

/// job.toml's text: job_toml(options), then the `[job]` table.
std::string job_record_toml(const JobRecord& record);

/// RUN_DIR/job.toml; InputError naming it when missing or malformed.
JobRecord read_job_record(const std::string& run_dir);

/// RUN_DIR/job.toml.
std::string job_record_path(const std::string& run_dir);

/// `run --resume` of `given` in a folder whose job is `job`: InputError
/// naming job.toml and the first difference: the build, an option that
/// changes the outputs (--threads, --debug-views, --keep-state and the
/// console options do not; output paths compare as absolute paths; the
/// exemplar by content; the input not at all here: the resumed run loads the
/// newest state against its frame's mesh, whose fingerprint it holds), or frames that do not continue the job's (one list must start
/// with the other: a resume may extend or shorten the range, not move its
/// start or step).
void check_resumable(const JobRecord& job, const JobRecord& given);

/// InputError naming `state_path` and the first option whose value in
/// `job` (a job.toml, or the command line of a --resume) differs from the
/// one the state was tracked with (`state`): a job.toml edited after
/// tracking, or a state of another job. An automatic option left to "auto"
/// in `job` takes whatever the tracker resolved.
void check_state_settings(const TrackerSettings& state, const JobOptions& job, const std::string& state_path);

/// The files in the output folder (and under the atlas and mesh patterns)
/// that a job of `options` writes: job.toml, stats.jsonl, stats/, state/,
/// the atlases, AOVs, UV meshes and debug views of any frame, and what
/// `fluidtex eval` and `preview` derived from them. Only those that exist.
std::vector<std::filesystem::path> existing_job_outputs(const JobOptions& options);

/// Before a run (not --resume) writes into OUT: InputError when OUT holds
/// another job's outputs (naming one), unless `options.output.force`, which
/// removes them all first (those of the job in OUT/job.toml too, when its
/// patterns differ). Returns how many files --force removed.
std::size_t claim_output_folder(const JobOptions& options);

}  // namespace fluidtex
