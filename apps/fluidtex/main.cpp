// fluidtex: temporally coherent texture on the free surface of fluid
// simulations (Gagnon et al. 2019). Exit codes: 0 success, 2 bad input
// (including bad options, a job that cannot be continued as recorded) or out
// of memory, 1 internal failure.
#include <clocale>
#include <cstdio>
#include <exception>
#include <locale>
#include <new>

#include "cli.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/memory.h"
#include "fluidtex/util/version.h"

int main(int argc, char** argv) {
  fluidtex::keep_freed_memory_for_reuse();
  std::setlocale(LC_ALL, "C");
  std::locale::global(std::locale::classic());
  CLI::App app{
      "fluidtex: temporally coherent texture synthesis on the free surface of fluids\n"
      "(deformable patches, Gagnon et al. 2019)",
      "fluidtex"};
  int exit_code = 0;
  try {
    app.require_subcommand(1);
    app.set_version_flag("--version", fluidtex::version_line());
    fluidtex::cli::add_subcommands(app, exit_code);
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // One line, like every other error (CLI11 would add "Run with --help ...").
    std::fprintf(stderr, "fluidtex: error: %s (see --help)\n", e.what());
    return 2;
  } catch (const fluidtex::InputError& e) {
    fluidtex::cli::print_error(e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    // Input sizes are bounded where they are read, so this is the job's size
    // against the machine's (or the farm slot's) memory: the user can fix it.
    fluidtex::cli::print_error("out of memory: lower --atlas-size or --threads, or give the job more memory");
    return 2;
  } catch (const std::exception& e) {
    fluidtex::cli::print_error(e.what(), true);
    return 1;
  }
  return exit_code;
}
