// The fluidtex command line: option binding and subcommand handlers. All
// work happens in the library; this only parses, reports and maps errors.
#pragma once

#include <CLI/CLI.hpp>

namespace fluidtex::cli {

/// Adds the subcommands to `app`. Each subcommand's callback stores the exit
/// code in `exit_code`.
void add_subcommands(CLI::App& app, int& exit_code);

/// Prints the one line of a failed command on stderr: "fluidtex: error:
/// MESSAGE" (`internal`: "fluidtex: internal error: ..."), or a JSON object
/// {"event":"error","internal":false,"message":...} after --log-format json.
void print_error(const std::string& message, bool internal = false);

}  // namespace fluidtex::cli
