#include "fluidtex/util/memory.h"

#include <malloc.h>

#include <climits>

namespace fluidtex {

void keep_freed_memory_for_reuse() {
  // Large blocks from the heap rather than from mmap (thread arenas still
  // map what exceeds their heap size), and no trimming of freed heap memory.
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, INT_MAX);
}

}  // namespace fluidtex
