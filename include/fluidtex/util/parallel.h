/// @file parallel.h
/// @brief f(i) for every i in [0, n) on oneTBB's pool. Each call must write
/// only its own slot, so results do not depend on the thread count.
#pragma once

#include <cstddef>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

namespace fluidtex {

template <class F>
void parallel_each(std::size_t n, F&& f) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) f(i);
  });
}

}  // namespace fluidtex
