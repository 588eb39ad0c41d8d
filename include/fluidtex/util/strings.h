/// @file strings.h
/// @brief Small string helpers shared by the readers and writers.
#pragma once

#include <string>

namespace fluidtex {

/// `s` in ASCII lower case (locale-independent).
std::string to_lower(std::string s);

/// The shortest text that reads back as exactly `v` ("0.1", "1e-06", "inf").
std::string format_number(double v);

/// The extension of `path` with its dot, in lower case ("" when none):
/// "a/B.PLY" → ".ply".
std::string lower_extension(const std::string& path);

/// `message` (a library's error, which may span lines) as one line: its
/// lines trimmed, repeats left out, joined by "; ".
std::string one_line(const std::string& message);

}  // namespace fluidtex
