#include "fluidtex/util/atomic_file.h"

#include <atomic>
#include <fstream>
#include <system_error>

#include <signal.h>
#include <unistd.h>

#include <cerrno>

#include "fluidtex/util/error.h"

namespace fluidtex {

namespace fs = std::filesystem;

fs::path temporary_sibling(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::string name = ".";
  name += target.stem().string();
  name += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  name += target.extension().string();
  return dir / name;
}

void write_atomically(const fs::path& target, const std::function<void(const fs::path& tmp)>& write) {
  std::error_code ec;
  if (target.has_parent_path()) {
    fs::create_directories(target.parent_path(), ec);
    if (ec) {
      throw InternalError(target.parent_path().string() + ": cannot create output folder: " + ec.message());
    }
  }
  const fs::path tmp = temporary_sibling(target);
  try {
    write(tmp);
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw InternalError(target.string() + ": cannot move the finished file into place: " + ec.message());
  }
}

std::size_t remove_stale_temporaries(const fs::path& dir) {
  std::error_code ec;
  std::size_t removed = 0;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    const std::size_t tag = name.find(".tmp-");
    if (name.empty() || name[0] != '.' || tag == std::string::npos) continue;
    const std::size_t dash = name.find('-', tag + 5);
    if (dash == std::string::npos) continue;
    long pid = 0;
    try {
      pid = std::stol(name.substr(tag + 5, dash - tag - 5));
    } catch (const std::exception&) {
      continue;
    }
    // A live writer (another job in the same folder, or this one) keeps its files.
    if (pid <= 0 || (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM)) continue;
    std::error_code rm;
    if (fs::remove(entry.path(), rm)) ++removed;
  }
  return removed;
}

void require_regular_file(const std::string& path, const std::string& what) {
  std::error_code ec;
  const fs::file_status link = fs::symlink_status(path, ec);
  if (!fs::exists(link)) throw InputError(path, what + " is missing (no such file)");
  const fs::file_status st = fs::status(path, ec);
  if (ec) {
    if (fs::is_symlink(link))
      throw InputError(path, what + " is a symbolic link that " +
                                 (ec == std::errc::too_many_symbolic_link_levels ? "loops" : "points nowhere"));
    throw InputError(path, what + " cannot be examined: " + ec.message());
  }
  if (fs::is_regular_file(st)) return;
  if (!fs::exists(st)) throw InputError(path, what + " is a symbolic link that points nowhere");
  const char* kind = fs::is_directory(st)        ? "a folder"
                     : fs::is_fifo(st)           ? "a FIFO"
                     : fs::is_block_file(st)     ? "a block device"
                     : fs::is_character_file(st) ? "a character device"
                     : fs::is_socket(st)         ? "a socket"
                                                 : "not a regular file";
  throw InputError(path, what + " is " + kind + ", not a regular file");
}

void write_text_atomically(const fs::path& target, const std::string& text) {
  write_atomically(target, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) throw InternalError(target.string() + ": cannot write file");
  });
}

}  // namespace fluidtex
