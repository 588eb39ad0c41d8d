/// @file atomic_file.h
/// @brief Files in and out. Outputs are never half-written: write to a
/// temporary name in the target's folder, then rename over the target (atomic
/// on POSIX file systems). Inputs are regular files only.
#pragma once

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

namespace fluidtex {

/// This machine's short host name as temporaries are tagged with it (no '.'
/// or '-').
const std::string& host_name();

/// A temporary path next to `target` whose extension is kept (image writers
/// pick the format from it): `dir/.STEM.tmp-<pid>-<n>-<host>.EXT`. The host
/// tells apart writers of different machines sharing the folder (a farm).
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

/// Closes `out`, the stream a `write_atomically` callback wrote `target`'s
/// temporary with, and throws InternalError("TARGET: cannot write file: <the
/// system's reason>", e.g. "No space left on device") when opening, writing or
/// closing failed.
void close_written(std::ofstream& out, const std::filesystem::path& target);

/// Removes the temporaries a killed run left in `dir` (not recursive):
/// those of this machine whose writer process is gone, and those of another
/// machine whose target file name (`NAME.EXT`) `owned` accepts (the caller
/// writes that file; the other machine's writer cannot be asked whether it
/// still runs). Returns how many were removed.
std::size_t remove_stale_temporaries(const std::filesystem::path& dir,
                                     const std::function<bool(const std::string&)>& owned = {});

/// InputError("PATH: <what> is ...") unless `path` is a regular file (or a
/// link to one): missing, a dangling link, a link loop, a folder, a FIFO, a
/// device or a socket is refused before anything opens it (opening a FIFO or
/// a device would block or never end).
void require_regular_file(const std::string& path, const std::string& what);

/// The whole file at `path`; InputError("PATH: cannot open file for reading")
/// or ("PATH: read error").
std::string read_file_bytes(const std::string& path);

}  // namespace fluidtex
