/// @file version.h
/// @brief Which build made an output: the version of the project and, when
/// built from a git checkout, its commit (refreshed on every build).
#pragma once

#include <string>

namespace fluidtex {

/// "0.1.0".
const char* version();

/// The commit the sources come from ("3af1a48c2d10", "…-dirty" with local
/// changes), or "" when not built from a git checkout.
const char* git_commit();

/// "fluidtex 0.1.0 (git 3af1a48c2d10)", or "fluidtex 0.1.0" outside a checkout.
std::string version_line();

}  // namespace fluidtex
