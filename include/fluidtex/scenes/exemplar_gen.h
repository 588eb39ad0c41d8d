/// @file exemplar_gen.h
/// @brief Procedural, tileable, stochastic exemplar textures made by the
/// project (nothing downloaded): `gravel` (Worley cells with per-cell tint and
/// value-noise grain) and `bubbles` (scattered soft rings on a dark liquid).
/// Deterministic for a seed; periodic in both directions so wrap lookups
/// show no seam.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fluidtex/geometry/image.h"

namespace fluidtex {

std::vector<std::string> exemplar_names();

/// RGB, linear float in [0,1]. Throws InputError for an unknown name or size < 8.
Image make_exemplar(const std::string& name, int size, std::uint64_t seed);

}  // namespace fluidtex
