// The command reference, written from the command line's own option
// tables: every subcommand with its description, every option with its
// names, value type, default and help, as `--help` prints them. Two forms:
// the manual page fluidtex(1) and docs/commands.md.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace fluidtex::cli {

/// fluidtex(1) in man(7) markup for `app` (with its subcommands added):
/// NAME, SYNOPSIS, DESCRIPTION, one subsection per subcommand, EXIT STATUS,
/// FILES, SEE ALSO. Options of an empty group (hidden from --help) are left
/// out.
std::string man_page(const CLI::App& app, const std::string& version);

/// docs/commands.md: the same reference in Markdown, one section per
/// subcommand in the order of --help. No version in it, so it changes only
/// when an option does.
std::string command_reference(const CLI::App& app);

}  // namespace fluidtex::cli
