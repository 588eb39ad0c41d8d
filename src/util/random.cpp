#include "fluidtex/util/random.h"

#include <cmath>

namespace fluidtex {

std::array<unsigned char, 3> id_color(std::uint32_t id) {
  // A random hue per id, full saturation, bright: distinct neighbours.
  const double h = to_unit(mix64(id + 0x51ed27ULL)) * 6.0;
  const double x = 1.0 - std::abs(std::fmod(h, 2.0) - 1.0);
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(h)) {
    case 0: r = 1, g = x; break;
    case 1: r = x, g = 1; break;
    case 2: g = 1, b = x; break;
    case 3: g = x, b = 1; break;
    case 4: r = x, b = 1; break;
    default: r = 1, b = x; break;
  }
  auto c = [](double v) { return static_cast<unsigned char>(40 + 215 * v); };
  return {c(r), c(g), c(b)};
}

}  // namespace fluidtex
