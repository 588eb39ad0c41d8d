// Procedural exemplar textures (the paper's Fig. 8 uses gravel, Fig. 9
// bubbles). Everything is periodic over the unit square: lattices wrap
// modulo their integer frequency, so the image tiles without a seam for any
// size. Random numbers come from a hash of (seed, stream, lattice cell), never
// from global state.
#include "fluidtex/scenes/exemplar_gen.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Core>

#include "fluidtex/util/error.h"

namespace fluidtex {

namespace {

using Vec2 = Eigen::Vector2d;

// --- Hashing -----------------------------------------------------------------
std::uint64_t mix64(std::uint64_t z) {
  // splitmix64 finaliser.
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

std::uint64_t hash(std::uint64_t seed, std::uint64_t stream, int i, int j, int k = 0) {
  std::uint64_t h = mix64(seed ^ mix64(stream));
  h = mix64(h ^ static_cast<std::uint32_t>(i));
  h = mix64(h ^ (static_cast<std::uint64_t>(static_cast<std::uint32_t>(j)) << 1));
  return mix64(h ^ (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k)) << 2));
}

/// Uniform in [0, 1) from a hash.
double unit(std::uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

int wrap(int i, int n) { return ((i % n) + n) % n; }

double smooth(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

/// Periodic value noise in [0, 1] on the unit square with `freq` cells.
double value_noise(std::uint64_t seed, std::uint64_t stream, double u, double v, int freq) {
  const double x = u * freq, y = v * freq;
  const int i = static_cast<int>(std::floor(x)), j = static_cast<int>(std::floor(y));
  const double fx = smooth(x - i), fy = smooth(y - j);
  auto at = [&](int a, int b) { return unit(hash(seed, stream, wrap(a, freq), wrap(b, freq))); };
  const double v0 = at(i, j) + fx * (at(i + 1, j) - at(i, j));
  const double v1 = at(i, j + 1) + fx * (at(i + 1, j + 1) - at(i, j + 1));
  return v0 + fy * (v1 - v0);
}

/// Periodic fractal sum of value noise, normalised to [0, 1].
double fbm(std::uint64_t seed, std::uint64_t stream, double u, double v, int freq, int octaves) {
  double sum = 0.0, norm = 0.0, amp = 1.0;
  for (int o = 0; o < octaves; ++o) {
    sum += amp * value_noise(seed, stream + o, u, v, freq << o);
    norm += amp;
    amp *= 0.5;
  }
  return sum / norm;
}

double smoothstep(double a, double b, double x) {
  const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

using Rgb = std::array<double, 3>;

Image make_image(int size) {
  Image img;
  img.width = img.height = size;
  img.channels = 3;
  img.pixels.assign(static_cast<std::size_t>(size) * size * 3, 0.0f);
  return img;
}

void put(Image& img, int x, int y, const Rgb& c) {
  for (int k = 0; k < 3; ++k) img.at(x, y, k) = static_cast<float>(std::clamp(c[k], 0.0, 1.0));
}

// --- gravel --------------------------------------------------------------------
// Worley cells (one jittered feature point per cell of a periodic lattice);
// F2 - F1 is the distance to the cell border: small values are the dark gaps
// between stones, larger ones the stone's rounded "height". Each stone gets
// a tint from a small palette and a brightness from its cell hash; the
// height field is lit from the top left and value-noise grain is added.
/// The distances from p to the nearest and second nearest feature points of
/// a periodic grid of cells × cells (Worley's F1, F2), searched in the 5 × 5
/// cells around (ci, cj), and the nearest one's cell.
struct NearestFeatures {
  double f1 = 1e9, f2 = 1e9;
  int best = 0;
};

NearestFeatures nearest_features(const Vec2& p, int ci, int cj, const std::vector<Vec2>& feature, int cells) {
  NearestFeatures out;
  for (int dj = -2; dj <= 2; ++dj) {
    for (int di = -2; di <= 2; ++di) {
      const int i = ci + di, j = cj + dj;
      const int c = wrap(j, cells) * cells + wrap(i, cells);
      const Vec2 q = feature[c] + Vec2(i - wrap(i, cells), j - wrap(j, cells));
      const double d = (p - q).norm();
      if (d < out.f1) {
        out.f2 = out.f1, out.f1 = d, out.best = c;
      } else if (d < out.f2) {
        out.f2 = d;
      }
    }
  }
  return out;
}

Image make_gravel(int size, std::uint64_t seed) {
  const int cells = std::clamp(size / 40, 4, 24);
  // Feature points, periodic.
  std::vector<Vec2> feature(static_cast<std::size_t>(cells) * cells);
  std::vector<Rgb> tint(feature.size());
  const Rgb palette[] = {{0.42, 0.38, 0.33}, {0.55, 0.50, 0.43}, {0.33, 0.32, 0.31},
                         {0.60, 0.56, 0.50}, {0.45, 0.37, 0.29}, {0.38, 0.39, 0.40}};
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      const std::size_t c = static_cast<std::size_t>(j) * cells + i;
      feature[c] = Vec2(i + 0.1 + 0.8 * unit(hash(seed, 1, i, j)), j + 0.1 + 0.8 * unit(hash(seed, 2, i, j)));
      const Rgb base = palette[hash(seed, 3, i, j) % std::size(palette)];
      const double bright = 0.75 + 0.5 * unit(hash(seed, 4, i, j));
      for (int k = 0; k < 3; ++k) tint[c][k] = base[k] * bright * (0.96 + 0.08 * unit(hash(seed, 5, i, j, k)));
    }
  }
  // Height field and stone id per pixel.
  const std::size_t n = static_cast<std::size_t>(size) * size;
  std::vector<double> height(n);
  std::vector<int> stone(n);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const double u = (x + 0.5) / size, v = (y + 0.5) / size;
      const Vec2 p(u * cells, v * cells);
      const int ci = static_cast<int>(std::floor(p.x())), cj = static_cast<int>(std::floor(p.y()));
      const NearestFeatures near = nearest_features(p, ci, cj, feature, cells);
      const double edge = near.f2 - near.f1;  // ~ twice the distance to the cell border
      // Warp the border slightly with noise so stones are not polygons.
      const double wobble = 0.12 * (fbm(seed, 10, u, v, 2 * cells, 2) - 0.5);
      const double e = edge + wobble;
      const std::size_t idx = texel_index(x, y, size);
      height[idx] = e <= 0.08 ? 0.0 : std::sqrt(smoothstep(0.08, 0.75, e));
      stone[idx] = near.best;
    }
  }
  Image img = make_image(size);
  const Vec2 light = Vec2(-1.0, -1.0).normalized();
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const std::size_t idx = texel_index(x, y, size);
      auto H = [&](int a, int b) { return height[static_cast<std::size_t>(wrap(b, size)) * size + wrap(a, size)]; };
      const Vec2 grad(H(x + 1, y) - H(x - 1, y), H(x, y + 1) - H(x, y - 1));
      const double slope_scale = 0.06 * size / cells;
      const double shade = std::clamp(0.8 - slope_scale * grad.dot(light), 0.35, 1.25);
      const double u = (x + 0.5) / size, v = (y + 0.5) / size;
      const double grain = 0.8 + 0.4 * fbm(seed, 20, u, v, 8 * cells, 3);
      const double speck = value_noise(seed, 30, u, v, 32 * cells) > 0.9 ? 0.75 : 1.0;
      const double stone_mask = smoothstep(0.0, 0.15, height[idx]);
      const Rgb& c = tint[stone[idx]];
      const double gap = 0.05 + 0.06 * fbm(seed, 40, u, v, 4 * cells, 2);
      Rgb out;
      for (int k = 0; k < 3; ++k) {
        const double lit = c[k] * shade * grain * speck * (0.8 + 0.2 * height[idx]);
        out[k] = stone_mask * lit + (1.0 - stone_mask) * gap * (k == 2 ? 0.9 : 1.0);
      }
      put(img, x, y, out);
    }
  }
  return img;
}

// --- bubbles -------------------------------------------------------------------
// A dark blue-green liquid (two-octave noise) with soft bright rings: each
// cell of a periodic lattice holds 0-2 bubbles with log-uniform radii (at
// most 0.9 cell, so a 5x5 cell neighbourhood sees every bubble that can
// touch a pixel), a bright rim, a faint fill and a small highlight.
Image make_bubbles(int size, std::uint64_t seed) {
  const int cells = std::clamp(size / 48, 3, 20);
  struct Bubble {
    Vec2 centre;
    double radius;
    double strength;
  };
  std::vector<std::vector<Bubble>> bubbles(static_cast<std::size_t>(cells) * cells);
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      const int count = 1 + static_cast<int>(hash(seed, 1, i, j) % 3) - (unit(hash(seed, 2, i, j)) < 0.25 ? 1 : 0);
      for (int b = 0; b < count; ++b) {
        Bubble bubble;
        bubble.centre = Vec2(i + unit(hash(seed, 3, i, j, b)), j + unit(hash(seed, 4, i, j, b)));
        bubble.radius = 0.08 * std::pow(0.85 / 0.08, unit(hash(seed, 5, i, j, b)));
        bubble.strength = 0.55 + 0.45 * unit(hash(seed, 6, i, j, b));
        bubbles[static_cast<std::size_t>(j) * cells + i].push_back(bubble);
      }
    }
  }
  Image img = make_image(size);
  const Rgb deep = {0.015, 0.06, 0.07}, shallow = {0.04, 0.17, 0.19};
  const Rgb rim = {0.80, 0.95, 1.0};
  const double pixel = static_cast<double>(cells) / size;  // one pixel in cell units
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const double u = (x + 0.5) / size, v = (y + 0.5) / size;
      const double n = fbm(seed, 50, u, v, 3, 4);
      Rgb c;
      for (int k = 0; k < 3; ++k) c[k] = deep[k] + (shallow[k] - deep[k]) * smoothstep(0.25, 0.75, n);
      const Vec2 p(u * cells, v * cells);
      const int ci = static_cast<int>(std::floor(p.x())), cj = static_cast<int>(std::floor(p.y()));
      double light = 0.0, fill = 0.0;
      for (int dj = -2; dj <= 2; ++dj) {
        for (int di = -2; di <= 2; ++di) {
          const int i = ci + di, j = cj + dj;
          const Vec2 shift(i - wrap(i, cells), j - wrap(j, cells));
          for (const Bubble& b : bubbles[static_cast<std::size_t>(wrap(j, cells)) * cells + wrap(i, cells)]) {
            const Vec2 d = p - (b.centre + shift);
            const double r = d.norm();
            if (r > b.radius * 1.3 + 3 * pixel) continue;
            const double width = 0.09 * b.radius + 1.2 * pixel;
            const double ring = std::exp(-std::pow((r - b.radius) / width, 2));
            const double inner = r < b.radius ? 0.12 * (1.0 - std::pow(r / b.radius, 2)) : 0.0;
            const Vec2 spot = d + 0.45 * b.radius * Vec2(1.0, 1.0).normalized();
            const double highlight = std::exp(-spot.squaredNorm() / std::pow(0.16 * b.radius + pixel, 2));
            light = std::max(light, b.strength * (ring + 0.9 * highlight));
            fill = std::max(fill, b.strength * inner);
          }
        }
      }
      const double grain = 0.9 + 0.2 * value_noise(seed, 60, u, v, 16 * cells);
      Rgb out;
      for (int k = 0; k < 3; ++k) out[k] = (c[k] + fill * rim[k] * 0.5) * grain + light * rim[k] * (1.0 - 0.3 * fill);
      put(img, x, y, out);
    }
  }
  return img;
}

}  // namespace

std::vector<std::string> exemplar_names() { return {"gravel", "bubbles"}; }

Image make_exemplar(const std::string& name, int size, std::uint64_t seed) {
  if (size < 8) throw InputError("", "invalid exemplar size " + std::to_string(size) + " (must be >= 8)");
  if (name == "gravel") return make_gravel(size, seed);
  if (name == "bubbles") return make_bubbles(size, seed);
  throw InputError("", "unknown exemplar '" + name + "' (known: gravel, bubbles)");
}

}  // namespace fluidtex
