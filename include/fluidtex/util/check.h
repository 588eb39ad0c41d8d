/// @file check.h
/// @brief Invariant checks that name the broken condition and print both
/// operands (as pbrt-v4's CHECK_EQ). A failed check is a bug, never bad
/// input: it throws InternalError (exit code 1) with the file, the line, the
/// condition and the values, so the library still never terminates the
/// application.
///
///   FLUIDTEX_CHECK(uv.size() == n);
///   FLUIDTEX_CHECK_EQ(uv.size(), mesh.num_vertices());  // "... (7 vs 9)"
///   FLUIDTEX_DCHECK_LT(i, texels.size());               // debug builds only
///
/// The DCHECK forms compile to nothing with NDEBUG (Release builds), for
/// checks in inner loops; their operands are not evaluated there.
#pragma once

#include <sstream>
#include <string>

#include "fluidtex/util/error.h"

namespace fluidtex::check_detail {

[[noreturn]] inline void fail(const char* file, int line, const std::string& what) {
  throw InternalError(std::string(file) + ":" + std::to_string(line) + ": check failed: " + what);
}

template <class A, class B>
[[noreturn]] void fail_op(const char* file, int line, const char* text, const A& a, const B& b) {
  std::ostringstream s;
  s << text << " (" << a << " vs " << b << ")";
  fail(file, line, s.str());
}

}  // namespace fluidtex::check_detail

#define FLUIDTEX_CHECK(cond)                                                \
  do {                                                                      \
    if (!(cond)) ::fluidtex::check_detail::fail(__FILE__, __LINE__, #cond); \
  } while (false)

#define FLUIDTEX_CHECK_OP(a, op, b)                                                                                 \
  do {                                                                                                              \
    const auto& fluidtex_check_a = (a);                                                                             \
    const auto& fluidtex_check_b = (b);                                                                             \
    if (!(fluidtex_check_a op fluidtex_check_b))                                                                    \
      ::fluidtex::check_detail::fail_op(__FILE__, __LINE__, #a " " #op " " #b, fluidtex_check_a, fluidtex_check_b); \
  } while (false)

#define FLUIDTEX_CHECK_EQ(a, b) FLUIDTEX_CHECK_OP(a, ==, b)
#define FLUIDTEX_CHECK_NE(a, b) FLUIDTEX_CHECK_OP(a, !=, b)
#define FLUIDTEX_CHECK_LT(a, b) FLUIDTEX_CHECK_OP(a, <, b)
#define FLUIDTEX_CHECK_LE(a, b) FLUIDTEX_CHECK_OP(a, <=, b)
#define FLUIDTEX_CHECK_GT(a, b) FLUIDTEX_CHECK_OP(a, >, b)
#define FLUIDTEX_CHECK_GE(a, b) FLUIDTEX_CHECK_OP(a, >=, b)

#ifdef NDEBUG
#define FLUIDTEX_DCHECK(cond) \
  do {                        \
  } while (false)
#define FLUIDTEX_DCHECK_OP(a, op, b) \
  do {                               \
  } while (false)
#else
#define FLUIDTEX_DCHECK(cond) FLUIDTEX_CHECK(cond)
#define FLUIDTEX_DCHECK_OP(a, op, b) FLUIDTEX_CHECK_OP(a, op, b)
#endif
#define FLUIDTEX_DCHECK_EQ(a, b) FLUIDTEX_DCHECK_OP(a, ==, b)
#define FLUIDTEX_DCHECK_LT(a, b) FLUIDTEX_DCHECK_OP(a, <, b)
#define FLUIDTEX_DCHECK_LE(a, b) FLUIDTEX_DCHECK_OP(a, <=, b)
#define FLUIDTEX_DCHECK_GE(a, b) FLUIDTEX_DCHECK_OP(a, >=, b)
