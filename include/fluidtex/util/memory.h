/// @file memory.h
/// @brief Process-wide memory settings for a frame-by-frame batch job.
#pragma once

#include <cstdint>
#include <optional>

namespace fluidtex {

/// The memory this process may use, in bytes: the least of the machine's
/// physical memory, the address-space limit (ulimit -v, a farm slot's) and
/// the cgroup's memory.max (a container's or a Slurm job's); nullopt when
/// none can be read.
std::optional<std::uint64_t> memory_limit_bytes();

/// Keeps freed memory in the process for the next frame: every frame
/// allocates and frees the same atlas-sized buffers (tens to hundreds of MB:
/// the colour image, the texel map, the writer's half-float copy), and by
/// default glibc maps each afresh and unmaps it when it is freed, so that
/// every frame pays the kernel's page faults and zero-filling again. The
/// process then holds on to its peak, which it reaches on every frame
/// anyway. For programs (the command line, the benchmark), not for a host
/// application that loads the library: call it once, first thing in main().
void keep_freed_memory_for_reuse();

}  // namespace fluidtex
