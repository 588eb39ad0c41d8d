#include "fluidtex/inspect/texture_metrics.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>

#include <unsupported/Eigen/FFT>

#include "fluidtex/geometry/mesh.h"
#include "fluidtex/util/check.h"
#include "fluidtex/util/error.h"

namespace fluidtex {

std::vector<char> chart_mask(const UVMesh& mesh, int size, const Vec2& origin) {
  std::vector<char> mask(static_cast<std::size_t>(size) * size, 0);
  for (const Tri& t : mesh.uv_triangles) {
    std::array<Vec2, 3> p;
    for (int k = 0; k < 3; ++k) {
      const Vec2 uv = mesh.uvs[t[k]] - origin;
      p[k] = Vec2(u_to_px(uv.x(), size), v_to_py(uv.y(), size));
    }
    const Vec2 lo = p[0].cwiseMin(p[1]).cwiseMin(p[2]), hi = p[0].cwiseMax(p[1]).cwiseMax(p[2]);
    const double area = (p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[2] - p[0]).x() * (p[1] - p[0]).y();
    if (area == 0.0) continue;
    for (int y = std::max(0, static_cast<int>(lo.y() - 0.5)); y <= std::min(size - 1, static_cast<int>(hi.y())); ++y) {
      for (int x = std::max(0, static_cast<int>(lo.x() - 0.5)); x <= std::min(size - 1, static_cast<int>(hi.x()));
           ++x) {
        const Vec2 q(x + 0.5, y + 0.5);
        auto edge = [&](const Vec2& a, const Vec2& b) {
          return ((b - a).x() * (q - a).y() - (q - a).x() * (b - a).y()) / area;
        };
        if (edge(p[0], p[1]) >= -1e-9 && edge(p[1], p[2]) >= -1e-9 && edge(p[2], p[0]) >= -1e-9) {
          mask[texel_index(x, y, size)] = 1;
        }
      }
    }
  }
  return mask;
}

std::vector<double> contrast_ratio(const Image& image, const std::vector<char>& mask, const Exemplar& exemplar,
                                   double scale) {
  const int nc = std::min(image.channels, exemplar.channels());
  std::vector<double> sum(nc, 0.0), sum2(nc, 0.0);
  std::size_t n = 0;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) continue;
    ++n;
    for (int c = 0; c < nc; ++c) {
      const double v = image.pixels[i * image.channels + c];
      sum[c] += v, sum2[c] += v * v;
    }
  }
  std::vector<double> ratio(nc, 0.0);
  if (n < 2) return ratio;
  const std::vector<double> reference = resampled_stddev(exemplar, scale);
  for (int c = 0; c < nc; ++c) {
    const double mean = sum[c] / n;
    const double sd = std::sqrt(std::max(0.0, sum2[c] / n - mean * mean));
    ratio[c] = reference[c] > 0.0 ? sd / reference[c] : 0.0;
  }
  return ratio;
}

std::vector<double> radial_log_spectrum(const Image& image, int x0, int y0, int n) {
  if (n < 8 || (n & (n - 1)) != 0) throw InternalError("radial_log_spectrum: n must be a power of two >= 8");
  if (x0 < 0 || y0 < 0 || x0 + n > image.width || y0 + n > image.height)
    throw InternalError("radial_log_spectrum: crop outside the image");
  // Luminance, mean removed, Hann window.
  std::vector<double> window(n);
  for (int i = 0; i < n; ++i) window[i] = 0.5 - 0.5 * std::cos(2.0 * M_PI * (i + 0.5) / n);
  std::vector<double> lum(static_cast<std::size_t>(n) * n);
  double mean = 0.0;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      lum[texel_index(x, y, n)] =
          luminance_at<double>(image, static_cast<std::size_t>(y0 + y) * image.width + (x0 + x));
      mean += lum[texel_index(x, y, n)];
    }
  }
  mean /= static_cast<double>(n) * n;
  // 2D FFT: rows, then columns.
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> grid(static_cast<std::size_t>(n) * n);
  std::vector<double> row(n);
  std::vector<std::complex<double>> out(n), col(n);
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) row[x] = (lum[texel_index(x, y, n)] - mean) * window[x] * window[y];
    fft.fwd(out, row);
    for (int x = 0; x < n; ++x) grid[texel_index(x, y, n)] = out[x];
  }
  for (int x = 0; x < n; ++x) {
    for (int y = 0; y < n; ++y) col[y] = grid[texel_index(x, y, n)];
    fft.fwd(out, col);
    for (int y = 0; y < n; ++y) grid[texel_index(x, y, n)] = out[y];
  }
  const int bins = n / 2;
  std::vector<double> power(bins, 0.0);
  std::vector<int> count(bins, 0);
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const int fx = x <= n / 2 ? x : x - n, fy = y <= n / 2 ? y : y - n;
      const int k = static_cast<int>(std::sqrt(static_cast<double>(fx * fx + fy * fy)));
      if (k < 1 || k >= bins) continue;
      power[k] += std::norm(grid[texel_index(x, y, n)]);
      ++count[k];
    }
  }
  std::vector<double> spectrum;
  for (int k = 1; k < bins; ++k) spectrum.push_back(std::log(power[k] / std::max(1, count[k]) + 1e-12));
  return spectrum;
}

double spectrum_distance(const std::vector<double>& a, const std::vector<double>& b) {
  FLUIDTEX_CHECK_EQ(a.size(), b.size());
  FLUIDTEX_CHECK(!a.empty());
  double sum = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) sum += (a[k] - b[k]) * (a[k] - b[k]);
  return std::sqrt(sum / static_cast<double>(a.size()));
}

Image exemplar_crop(const Exemplar& exemplar, double x0, double y0, double scale, int n) {
  Image out;
  out.width = out.height = n;
  out.channels = exemplar.channels();
  out.pixels.resize(static_cast<std::size_t>(n) * n * out.channels);
  const int w = exemplar.image().width, h = exemplar.image().height;
  float px[3];
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      exemplar.sample(px_to_u(x0 + (x + 0.5) * scale, w), py_to_v(y0 + (y + 0.5) * scale, h), px);
      for (int c = 0; c < out.channels; ++c) out.at(x, y, c) = px[c];
    }
  }
  return out;
}

/// n×n windows of the atlas lying inside the charts, at most `limit`, spread
/// over the candidates in scan order (deterministic).
std::vector<std::pair<int, int>> chart_windows(const std::vector<char>& mask, int size, int n, int limit) {
  std::vector<std::uint32_t> sat(static_cast<std::size_t>(size + 1) * (size + 1), 0);  // summed-area table
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      sat[static_cast<std::size_t>(y + 1) * (size + 1) + x + 1] =
          mask[static_cast<std::size_t>(y) * size + x] + sat[static_cast<std::size_t>(y) * (size + 1) + x + 1] +
          sat[static_cast<std::size_t>(y + 1) * (size + 1) + x] - sat[static_cast<std::size_t>(y) * (size + 1) + x];
    }
  }
  std::vector<std::pair<int, int>> all;
  for (int y = 0; y + n <= size; y += n / 2) {
    for (int x = 0; x + n <= size; x += n / 2) {
      auto S = [&](int xx, int yy) { return sat[static_cast<std::size_t>(yy) * (size + 1) + xx]; };
      if (S(x + n, y + n) - S(x, y + n) - S(x + n, y) + S(x, y) == static_cast<std::uint32_t>(n * n))
        all.emplace_back(x, y);
    }
  }
  if (static_cast<int>(all.size()) <= limit) return all;
  std::vector<std::pair<int, int>> out;
  out.reserve(static_cast<std::size_t>(limit));
  for (int k = 0; k < limit; ++k) out.push_back(all[static_cast<std::size_t>(k) * all.size() / limit]);
  return out;
}

/// Texels per scene unit of a UV mesh in a size² atlas (area ratio).
double texel_density(const UVMesh& mesh, int size) {
  double a3 = 0.0, a2 = 0.0;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const Tri& t = mesh.triangles[f];
    a3 += triangle_area(mesh.positions, t);
    a2 += triangle_area(mesh.uvs, mesh.uv_triangles[f]) * size * size;
  }
  return a3 > 0.0 ? std::sqrt(a2 / a3) : 0.0;
}

std::vector<Image> exemplar_tiles(const Exemplar& exemplar, double scale, int crops) {
  FLUIDTEX_CHECK_GT(scale, 0.0);
  const int w = exemplar.image().width, h = exemplar.image().height;
  const int side = static_cast<int>(std::clamp(std::ceil(std::max(w, h) / scale), 64.0, 512.0));
  std::vector<Image> tiles;
  tiles.reserve(static_cast<std::size_t>(std::max(0, crops)));
  for (int k = 0; k < crops; ++k) tiles.push_back(exemplar_crop(exemplar, w * (0.37 * k), h * (0.61 * k), scale, side));
  return tiles;
}

std::vector<double> resampled_stddev(const Exemplar& exemplar, double scale) {
  const int nc = exemplar.channels();
  std::vector<double> sum(nc, 0.0), sum2(nc, 0.0);
  std::size_t n = 0;
  for (const Image& tile : exemplar_tiles(exemplar, scale)) {
    for (std::size_t i = 0; i < tile.pixels.size(); i += nc) {
      for (int c = 0; c < nc; ++c) {
        const double v = tile.pixels[i + c];
        sum[c] += v, sum2[c] += v * v;
      }
    }
    n += tile.pixels.size() / nc;
  }
  std::vector<double> sd(nc, 0.0);
  for (int c = 0; c < nc; ++c) {
    const double mean = sum[c] / static_cast<double>(n);
    sd[c] = std::sqrt(std::max(0.0, sum2[c] / static_cast<double>(n) - mean * mean));
  }
  return sd;
}

std::vector<double> exemplar_spectrum(const Exemplar& exemplar, double scale, int n, int crops) {
  std::vector<double> mean(static_cast<std::size_t>(n / 2 - 1), 0.0);
  for (int k = 0; k < crops; ++k) {
    const Image crop =
        exemplar_crop(exemplar, exemplar.image().width * (0.37 * k), exemplar.image().height * (0.61 * k), scale, n);
    const std::vector<double> s = radial_log_spectrum(crop, 0, 0, n);
    for (std::size_t b = 0; b < s.size(); ++b) mean[b] += s[b] / crops;
  }
  return mean;
}

namespace {

/// `s` less its mean: the shape of a log spectrum, whatever the contrast.
std::vector<double> shape_of(std::vector<double> s) {
  double mean = 0.0;
  for (double v : s) mean += v / static_cast<double>(s.size());
  for (double& v : s) v -= mean;
  return s;
}

}  // namespace

double measured_exemplar_span(const Image& atlas, const UVMesh& mesh, const Exemplar& exemplar, double expected) {
  const std::vector<char> mask = chart_mask(mesh, atlas.width);
  const double density = texel_density(mesh, atlas.width);
  if (!(density > 0.0) || !(expected > 0.0)) return std::nan("");
  for (int n : {64, 32, 16}) {
    const auto windows = chart_windows(mask, atlas.width, n, 64);
    if (windows.empty()) continue;
    std::vector<double> shown(static_cast<std::size_t>(n / 2 - 1), 0.0);
    for (const auto& [x, y] : windows) {
      const std::vector<double> s = radial_log_spectrum(atlas, x, y, n);
      for (std::size_t b = 0; b < s.size(); ++b) shown[b] += s[b] / static_cast<double>(windows.size());
    }
    shown = shape_of(std::move(shown));
    // Spans expected · 4^(k/24 − 1), k = 0 .. 48: steps of 5.9 %.
    constexpr int kSteps = 48;
    const double log_step = std::log(4.0) / (kSteps / 2);
    auto log_span = [&](double k) { return std::log(expected) + log_step * (k - kSteps / 2); };
    std::vector<double> distance(kSteps + 1);
    for (int k = 0; k <= kSteps; ++k) {
      const double scale = exemplar.image().width / (std::exp(log_span(k)) * density);
      distance[static_cast<std::size_t>(k)] = spectrum_distance(shown, shape_of(exemplar_spectrum(exemplar, scale, n)));
    }
    const int best = static_cast<int>(std::min_element(distance.begin(), distance.end()) - distance.begin());
    double offset = 0.0;  // the parabola's vertex through the best step and its neighbours
    if (best > 0 && best < kSteps) {
      const double a = distance[best - 1], b = distance[best], c = distance[best + 1];
      const double curvature = a - 2.0 * b + c;
      if (curvature > 0.0) offset = std::clamp(0.5 * (a - c) / curvature, -0.5, 0.5);
    }
    return std::exp(log_span(best + offset));
  }
  return std::nan("");
}

}  // namespace fluidtex
