// Runs the fluidtex command line in a process of its own without starting
// the executable: a server forked from the test binary before any test runs
// (one thread, every shared library already loaded and relocated) forks a
// copy of itself per command, which calls the command line's entry point and
// exits with its exit code. Starting the executable loads and relocates
// about 270 shared libraries (OpenImageIO's), about half a second of CPU,
// which the hostile-input suite paid twice per case. What runs is the same
// code from the same pristine state; the executable's own start is covered by
// the tests that run it (FLUIDTEX_EXE).
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace fluidtex::test {

/// Forks the server. Call first thing in main(), while the process has one
/// thread; afterwards the server answers spawn_command_line(). Without it
/// (the server failed to start), spawn_command_line() throws.
void start_cli_server();

/// What a command runs under: the folder, the files its stdout and stderr
/// go to, and RLIMIT_AS (0: none) and RLIMIT_CPU in bytes and seconds.
/// With `executable` the process runs that file (exec) instead of the entry
/// point it already has: for limits that the test binary's own address
/// space would not fit under.
struct CommandSetup {
  std::filesystem::path cwd, stdout_file, stderr_file;
  std::filesystem::path executable;
  std::uint64_t memory_limit = 0;
  unsigned cpu_seconds = 120;
};

/// A command started by spawn_command_line().
struct Command {
  pid_t pid = -1;
};

/// Starts `fluidtex ARGS` (args without the program name) under `setup`.
Command spawn_command_line(const std::vector<std::string>& args, const CommandSetup& setup);

/// Waits up to `seconds` for the command; returns true with its wait status
/// in `status` if it ended, false if it is still running.
bool wait_command_line(const Command& command, double seconds, int& status);

}  // namespace fluidtex::test
