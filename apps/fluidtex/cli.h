// The fluidtex command line: option binding and subcommand handlers. All
// work happens in the library; this only parses, reports and maps errors.
#pragma once

#include <CLI/CLI.hpp>

namespace fluidtex::cli {

/// The command line: parses `argv`, runs the subcommand and returns the
/// exit code (0 success, 2 bad input or out of memory, 1 internal failure),
/// having printed any error as one line.
int run_command_line(int argc, char** argv);

/// Adds the subcommands to `app`. Each subcommand's callback stores the exit
/// code in `exit_code`.
void add_subcommands(CLI::App& app, int& exit_code);

/// Prints the one line of a failed command on stderr: "fluidtex: error:
/// MESSAGE" (`internal`: "fluidtex: internal error: ..."), or a JSON object
/// {"event":"error","internal":false,"message":...} after --log-format json.
void print_error(const std::string& message, bool internal = false);

}  // namespace fluidtex::cli
