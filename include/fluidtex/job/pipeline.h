/// @file pipeline.h
/// @brief `fluidtex run`: the whole job over a sequence, frame by frame.
#pragma once

#include "fluidtex/job/frame_runner.h"
#include "fluidtex/job/job_options.h"
#include "fluidtex/util/report.h"

namespace fluidtex {

/// Runs the job (either method). Throws InputError for bad input (before any output is
/// written when the problem can be seen up front), InternalError otherwise.
JobSummary run_job(const JobOptions& requested, Reporter& reporter);

}  // namespace fluidtex
