#include "fluidtex/util/memory.h"

#include <malloc.h>
#include <sys/resource.h>

#include <algorithm>
#include <charconv>
#include <climits>
#include <fstream>
#include <string>

#include <OpenImageIO/sysutil.h>

namespace fluidtex {

std::optional<std::uint64_t> memory_limit_bytes() {
  std::optional<std::uint64_t> limit;
  const auto lower = [&](std::uint64_t bytes) { limit = limit ? std::min(*limit, bytes) : bytes; };
  if (const std::size_t physical = OIIO::Sysutil::physical_memory(); physical > 0) lower(physical);
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) lower(as.rlim_cur);
  std::ifstream cgroup("/sys/fs/cgroup/memory.max");  // cgroup v2; "max" when unlimited
  std::string text;
  std::uint64_t bytes = 0;
  if (cgroup >> text && std::from_chars(text.data(), text.data() + text.size(), bytes).ec == std::errc()) lower(bytes);
  return limit;
}

void keep_freed_memory_for_reuse() {
  // Large blocks from the heap rather than from mmap (thread arenas still
  // map what exceeds their heap size), and no trimming of freed heap memory.
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, INT_MAX);
}

}  // namespace fluidtex
