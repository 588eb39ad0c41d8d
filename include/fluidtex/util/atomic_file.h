/// @file atomic_file.h
/// @brief No half-written outputs: write to a temporary name in the target's
/// folder, then rename over the target (atomic on POSIX file systems).
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace fluidtex {

/// A temporary path next to `target` whose extension is kept (image writers
/// pick the format from it): `dir/.name.tmp-<pid>-<n>.ext`.
std::filesystem::path temporary_sibling(const std::filesystem::path& target);

/// Creates `target`'s parent folders, calls `write(tmp)` to write the whole
/// file under a temporary sibling name, then renames it over `target`. If
/// `write` throws, the temporary file is removed and the exception propagates;
/// `target` is never left partially written. Throws InternalError when the
/// folder cannot be created or the rename fails.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path& tmp)>& write);

/// Writes `text` to `target` atomically.
void write_text_atomically(const std::filesystem::path& target, const std::string& text);

}  // namespace fluidtex
