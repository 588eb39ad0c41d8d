// The fluidtex command line: option binding and subcommand handlers. All
// work happens in the library; this only parses, reports and maps errors.
#pragma once

#include <CLI/CLI.hpp>

namespace fluidtex::cli {

/// Adds the run / info / gen subcommands to `app`. Each subcommand's callback
/// stores the exit code in `exit_code`.
void add_subcommands(CLI::App& app, int& exit_code);

}  // namespace fluidtex::cli
