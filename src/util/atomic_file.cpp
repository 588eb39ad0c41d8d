#include "fluidtex/util/atomic_file.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <system_error>

#include <signal.h>
#include <unistd.h>

#include <cerrno>

#include "fluidtex/util/error.h"

namespace fluidtex {

namespace fs = std::filesystem;

const std::string& host_name() {
  static const std::string name = [] {
    char buf[256] = {};
    if (::gethostname(buf, sizeof buf - 1) != 0) return std::string("localhost");
    std::string host(buf);
    host = host.substr(0, host.find('.'));  // the short name: no '.' in a temporary's tag
    std::erase_if(host, [](char c) { return c == '-' || c == '/' || c == '\\'; });
    return host.empty() ? std::string("localhost") : host;
  }();
  return name;
}

namespace {

/// The parts of a temporary's name `.STEM.tmp-PID-N-HOST.EXT`: the target's
/// file name, the writer's pid and host. False for any other name. Names of
/// fluidtex 0.1 (`.STEM.tmp-PID-N.EXT`) have an empty host.
bool parse_temporary(const std::string& name, std::string& target, long& pid, std::string& host) {
  const std::size_t tag = name.find(".tmp-");
  if (name.empty() || name[0] != '.' || tag == std::string::npos) return false;
  const std::size_t dash = name.find('-', tag + 5);
  if (dash == std::string::npos) return false;
  try {
    std::size_t used = 0;
    const std::string digits = name.substr(tag + 5, dash - tag - 5);
    pid = std::stol(digits, &used);
    if (used != digits.size()) return false;
  } catch (const std::exception&) {
    return false;
  }
  std::size_t end = dash + 1;
  while (end < name.size() && std::isdigit(static_cast<unsigned char>(name[end]))) ++end;
  if (end == dash + 1) return false;
  host.clear();
  if (end < name.size() && name[end] == '-') {
    const std::size_t dot = name.find('.', end + 1);
    host = name.substr(end + 1, dot == std::string::npos ? std::string::npos : dot - end - 1);
    end = dot == std::string::npos ? name.size() : dot;
  }
  target = name.substr(1, tag - 1) + name.substr(end);
  return true;
}

}  // namespace

fs::path temporary_sibling(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::string name = ".";
  name += target.stem().string();
  name += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" + host_name();
  name += target.extension().string();
  return dir / name;
}

namespace {

/// Free bytes under which a failed write is put down to a full disk.
constexpr std::uintmax_t kFullDiskBytes = 1 << 20;

/// " (No space left on device: N bytes free in DIR)" when the file system of
/// `dir` is full, else "": writers that fail on a full disk (OpenEXR, TIFF)
/// seldom say why. Asked before the partial file is removed.
std::string full_disk_note(const fs::path& dir) {
  std::error_code ec;
  const fs::space_info space = fs::space(dir, ec);
  if (ec || space.available >= kFullDiskBytes) return "";
  return " (" + std::generic_category().message(ENOSPC) + ": " + std::to_string(space.available) + " bytes free in " +
         dir.string() + ")";
}

}  // namespace

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
  } catch (const std::exception& e) {
    const std::string what = e.what();
    const std::string note = what.find(std::generic_category().message(ENOSPC)) == std::string::npos
                                 ? full_disk_note(tmp.parent_path())
                                 : "";
    fs::remove(tmp, ec);
    if (note.empty()) throw;
    if (const auto* input = dynamic_cast<const InputError*>(&e))
      throw InputError(input->file(), input->problem() + note);
    throw InternalError(what + note);
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw InternalError(target.string() + ": cannot move the finished file into place: " + ec.message());
  }
}

std::size_t remove_stale_temporaries(const fs::path& dir, const std::function<bool(const std::string&)>& owned) {
  std::error_code ec;
  std::size_t removed = 0;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    std::string target, host;
    long pid = 0;
    if (!parse_temporary(entry.path().filename().string(), target, pid, host) || pid <= 0) continue;
    if (!host.empty() && host != host_name()) {
      // Another machine's writer cannot be asked whether it still runs: its
      // temporaries go only when the caller owns their target.
      if (!owned || !owned(target)) continue;
    } else if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM) {
      continue;  // a live writer (another job in the same folder, or this one) keeps its files
    }
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
    close_written(out, target);
  });
}

void close_written(std::ofstream& out, const fs::path& target) {
  if (out.is_open()) out.close();
  if (out) return;
  // The stream keeps no error code; the failed system call left it in errno.
  const int code = errno;
  throw InternalError(target.string() + ": cannot write file: " +
                      (code != 0 ? std::generic_category().message(code) : std::string("the write failed")));
}

std::string read_file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw InputError(path, "cannot open file for reading");
  std::string bytes(static_cast<std::size_t>(in.tellg()), '\0');
  in.seekg(0);
  if (!in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()))) throw InputError(path, "read error");
  return bytes;
}

}  // namespace fluidtex
