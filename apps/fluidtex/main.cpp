// fluidtex: temporally coherent texture on the free surface of fluid
// simulations (Gagnon et al. 2019). Exit codes: 0 success, 2 bad input
// (including bad options, a job that cannot be continued as recorded) or out
// of memory, 1 internal failure.
#include "cli.h"

int main(int argc, char** argv) { return fluidtex::cli::run_command_line(argc, argv); }
