// The tests' main: gtest's, after starting the command-line server
// (cli_server.h) while the process still has one thread.
#include <gtest/gtest.h>

#include "cli_server.h"

int main(int argc, char** argv) {
  fluidtex::test::start_cli_server();
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
