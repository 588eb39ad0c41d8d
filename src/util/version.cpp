#include "fluidtex/util/version.h"

#include "build_stamp.h"  // FLUIDTEX_GIT_COMMIT, written at build time

namespace fluidtex {

const char* version() { return FLUIDTEX_VERSION; }

const char* git_commit() { return FLUIDTEX_GIT_COMMIT; }

std::string version_line() {
  std::string line = std::string("fluidtex ") + version();
  if (*git_commit() != '\0') line += std::string(" (git ") + git_commit() + ")";
  return line;
}

}  // namespace fluidtex
