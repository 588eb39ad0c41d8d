/// @file error.h
/// @brief Typed errors. Library code never terminates the application: it throws
/// one of these and the command-line tool maps them to exit codes
/// (InputError -> 2, anything else -> 1).
#pragma once

#include <stdexcept>
#include <string>

namespace fluidtex {

/// Bad user input: a missing or truncated file, a mesh without velocities,
/// NaN/Inf values, an empty frame, a malformed frame pattern, an unreadable
/// exemplar, an invalid option value. `what()` is one line:
/// "<file>: <problem>" (or just "<problem>" when no file is involved).
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, const std::string& problem)
      : std::runtime_error(file.empty() ? problem : file + ": " + problem), file_(file), problem_(problem) {}
  const std::string& file() const { return file_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string file_;
  std::string problem_;
};

/// A failure that is not the user's input: an output folder that cannot be
/// written, a library call that failed unexpectedly.
class InternalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace fluidtex
