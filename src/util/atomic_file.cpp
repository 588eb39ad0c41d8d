#include "fluidtex/util/atomic_file.h"

#include <atomic>
#include <fstream>
#include <system_error>

#include <unistd.h>

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

void write_text_atomically(const fs::path& target, const std::string& text) {
  write_atomically(target, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) throw InternalError(target.string() + ": cannot write file");
  });
}

}  // namespace fluidtex
