/// @file random.h
/// @brief Counter-based randomness: every random number is a hash of
/// (seed, stream, item...), so results never depend on thread scheduling or
/// on the order in which items are visited (as in pbrt-v4).
#pragma once

#include <array>
#include <cstdint>
#include <initializer_list>

namespace fluidtex {

/// SplitMix64 finaliser.
inline std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// Hash of a list of integers.
inline std::uint64_t hash_values(std::initializer_list<std::uint64_t> values) {
  std::uint64_t h = 0x6a09e667f3bcc909ULL;
  for (std::uint64_t v : values) h = mix64(h ^ mix64(v));
  return h;
}

/// Uniform double in [0, 1) from a hash.
inline double to_unit(std::uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

/// Named streams, so that two uses of the same (seed, item) never correlate.
enum class Stream : std::uint64_t {
  Candidates = 1,
  CandidateOrder = 2,
  PatchAnchor = 3,
  Exemplar = 4,
  Evaluation = 5,
  FlowMapAnchor = 6,
};

inline double uniform(std::uint64_t seed, Stream stream, std::uint64_t a, std::uint64_t b = 0, std::uint64_t c = 0) {
  return to_unit(hash_values({seed, static_cast<std::uint64_t>(stream), a, b, c}));
}

/// A distinct, stable colour per id (8-bit RGB): a random hue, full
/// saturation, bright (patch ids in debug views, AOVs and overlays).
std::array<unsigned char, 3> id_color(std::uint32_t id);

}  // namespace fluidtex
