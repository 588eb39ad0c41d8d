#include "fluidtex/inspect/eval.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>

#include <OpenImageIO/color.h>
#include <OpenImageIO/strutil.h>
#include <oneapi/tbb/parallel_for.h>
#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>
#include <unsupported/Eigen/FFT>

#include "fluidtex/geometry/distortion.h"
#include "fluidtex/geometry/surface.h"
#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/io/sequence.h"
#include "fluidtex/io/uv_mesh_io.h"
#include "fluidtex/job/frame_texturing.h"
#include "fluidtex/job/job_layout.h"
#include "fluidtex/texture/synthesis.h"
#include "fluidtex/tracking/patch_coverage.h"
#include "fluidtex/tracking/surface_change.h"
#include "fluidtex/tracking/tracker.h"
#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/check.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/json.h"
#include "fluidtex/util/random.h"

namespace fluidtex {

std::vector<char> chart_mask(const UVMesh& mesh, int size) {
  std::vector<char> mask(static_cast<std::size_t>(size) * size, 0);
  for (const Tri& t : mesh.uv_triangles) {
    std::array<Vec2, 3> p;
    for (int k = 0; k < 3; ++k) p[k] = Vec2(u_to_px(mesh.uvs[t[k]].x(), size), v_to_py(mesh.uvs[t[k]].y(), size));
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

std::vector<double> contrast_ratio(const Image& image, const std::vector<char>& mask, const Exemplar& exemplar) {
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
  for (int c = 0; c < nc; ++c) {
    const double mean = sum[c] / n;
    const double sd = std::sqrt(std::max(0.0, sum2[c] / n - mean * mean));
    ratio[c] = exemplar.stddev()[c] > 0.0f ? sd / exemplar.stddev()[c] : 0.0;
  }
  return ratio;
}

namespace {

double luminance(const Image& image, std::size_t i) {
  const float* p = &image.pixels[i * image.channels];
  return image.channels >= 3 ? rec709_luminance<double>(p[0], p[1], p[2]) : p[0];
}

}  // namespace

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
      lum[texel_index(x, y, n)] = luminance(image, static_cast<std::size_t>(y0 + y) * image.width + (x0 + x));
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

TexturedFrame::TexturedFrame(UVMesh m, Image a) : mesh(std::move(m)), atlas(std::move(a)) {
  auto g = std::make_unique<FrameMesh>();
  g->positions = mesh.positions;
  g->triangles = mesh.triangles;
  g->velocities.assign(mesh.positions.size(), Vec3::Zero());
  geometry = std::move(g);  // on the heap: the index keeps its address when the frame is moved
  surface = std::make_unique<SurfaceIndex>(*geometry);
}

void TexturedFrame::color_at(const Vec3& p, float* out) const {
  const SurfacePoint s = surface->closest_point(p);
  if (!s.valid()) {
    for (int c = 0; c < atlas.channels; ++c) out[c] = 0.0f;
    return;
  }
  const Tri& t = mesh.uv_triangles[s.face];
  const Vec2 uv = interpolate(mesh.uvs, t, s.bary);
  sample_bilinear(atlas, u_to_px(uv.x(), atlas.width), v_to_py(uv.y(), atlas.height), out);
}

std::vector<std::pair<int, Vec3>> surface_samples(const FrameMesh& mesh, int count, std::uint64_t seed,
                                                  std::uint64_t salt) {
  std::vector<double> cumulative;
  double total = 0.0;
  for (const Tri& t : mesh.triangles) {
    total += triangle_area(mesh.positions, t);
    cumulative.push_back(total);
  }
  std::vector<std::pair<int, Vec3>> out;
  if (!(total > 0.0)) return out;
  for (int i = 0; i < count; ++i) {
    const double r = uniform(seed, Stream::Evaluation, salt, static_cast<std::uint64_t>(i), 0) * total;
    const int f = static_cast<int>(std::min<std::size_t>(
        std::upper_bound(cumulative.begin(), cumulative.end(), r) - cumulative.begin(), cumulative.size() - 1));
    double a = uniform(seed, Stream::Evaluation, salt, static_cast<std::uint64_t>(i), 1);
    double b = uniform(seed, Stream::Evaluation, salt, static_cast<std::uint64_t>(i), 2);
    if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
    out.emplace_back(f, Vec3(1.0 - a - b, a, b));
  }
  return out;
}

namespace {

Vec3 point_of(const FrameMesh& mesh, int f, const Vec3& bary, const std::vector<Vec3>& attribute) {
  const Tri& t = mesh.triangles[f];
  return interpolate(attribute, t, bary);
}

}  // namespace

struct LiquidMotion::Step {
  std::shared_ptr<const FrameMesh> mesh;  // the index refers to it
  SurfaceIndex surface;
  double dt;
  Step(std::shared_ptr<const FrameMesh> m, double seconds) : mesh(std::move(m)), surface(*mesh), dt(seconds) {}
};

void LiquidMotion::add_step(std::shared_ptr<const FrameMesh> mesh, double dt) {
  steps_.push_back(std::make_shared<const Step>(std::move(mesh), dt));
}

Vec3 LiquidMotion::carry(const Vec3& p, const Vec3& v) const {
  Vec3 q = p + v * dt_;
  for (const auto& step : steps_) {
    const SurfacePoint s = step->surface.closest_point(q);
    if (s.valid()) q += step->surface.velocity_at(s) * step->dt;
  }
  return q;
}

WarpingError warping_error(const FrameMesh& mesh, const TexturedFrame& at_t, const TexturedFrame& at_next,
                           const LiquidMotion& motion, const Exemplar& exemplar, int samples, std::uint64_t seed) {
  const auto points = surface_samples(mesh, samples, seed, 1);
  const auto others = surface_samples(*at_next.geometry, samples, seed, 2);
  WarpingError out;
  const int nc = std::min(at_t.atlas.channels, at_next.atlas.channels);
  double sigma = 0.0;
  for (int c = 0; c < nc; ++c) sigma += exemplar.stddev()[std::min(c, exemplar.channels() - 1)];
  sigma = std::max(sigma / nc, 1e-6);
  std::vector<std::array<double, 3>> err(points.size(), {0.0, 0.0, 0.0});
  tbb::parallel_for(std::size_t(0), points.size(), [&](std::size_t i) {
    const auto& [f, bary] = points[i];
    const Vec3 p = point_of(mesh, f, bary, mesh.positions);
    const Vec3 v = point_of(mesh, f, bary, mesh.velocities);
    float c0[kMaxLookupChannels], c1[kMaxLookupChannels], c2[kMaxLookupChannels], c3[kMaxLookupChannels];
    at_t.color_at(p, c0);
    at_next.color_at(motion.carry(p, v), c1);
    at_next.color_at(p, c2);
    const auto& [g, gb] = others[i];
    at_next.color_at(point_of(*at_next.geometry, g, gb, at_next.geometry->positions), c3);
    for (int c = 0; c < nc; ++c) {
      err[i][0] += std::abs(c1[c] - c0[c]) / nc;
      err[i][1] += std::abs(c2[c] - c0[c]) / nc;
      err[i][2] += std::abs(c3[c] - c0[c]) / nc;
    }
  });
  for (const auto& e : err) out.advected += e[0], out.fixed += e[1], out.random += e[2];  // in order
  out.samples = points.size();
  if (out.samples > 0) {
    const double k = 1.0 / (static_cast<double>(out.samples) * sigma);
    out.advected *= k, out.fixed *= k, out.random *= k;
  }
  return out;
}

FlowError optical_flow_error(const Image& a, const Image& b, const Image& expected, const std::vector<char>& mask,
                             double max_motion) {
  FLUIDTEX_CHECK(a.width == b.width && a.height == b.height);
  FLUIDTEX_CHECK(expected.width == a.width && expected.height == a.height);
  FLUIDTEX_CHECK_EQ(expected.channels, 2);
  FLUIDTEX_CHECK_EQ(mask.size(), texel_index(0, a.height, a.width));
  auto grey8 = [](const Image& im) {
    cv::Mat out(im.height, im.width, CV_8UC1);
    for (int y = 0; y < im.height; ++y) {
      for (int x = 0; x < im.width; ++x) {
        const double l = luminance(im, texel_index(x, y, im.width));
        // sRGB-encoded: the flow sees the contrast a viewer sees.
        const double e = OIIO::linear_to_sRGB(static_cast<float>(std::max(l, 0.0)));
        out.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(std::clamp(e * 255.0 + 0.5, 0.0, 255.0));
      }
    }
    return out;
  };
  const cv::Mat ga = grey8(a), gb = grey8(b);
  cv::Mat flow;
  cv::calcOpticalFlowFarneback(ga, gb, flow, 0.5, 4, 15, 5, 7, 1.5, 0);
  FlowError out;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      const std::size_t i = texel_index(x, y, a.width);
      if (!mask[i]) continue;
      const cv::Point2f f = flow.at<cv::Point2f>(y, x);
      const double ex = expected.pixels[2 * i], ey = expected.pixels[2 * i + 1];
      const double endpoint = std::hypot(f.x - ex, f.y - ey), speed = std::hypot(ex, ey);
      out.endpoint += endpoint;
      out.speed += speed;
      if (speed < max_motion) out.slow_endpoint += endpoint, out.slow_speed += speed, ++out.slow_pixels;
      const double dot = f.x * ex + f.y * ey + 1.0;
      const double na = std::sqrt(f.x * f.x + f.y * f.y + 1.0), nb = std::sqrt(ex * ex + ey * ey + 1.0);
      out.angular += std::acos(std::clamp(dot / (na * nb), -1.0, 1.0)) * 180.0 / M_PI;
      ++out.pixels;
    }
  }
  if (out.pixels > 0) out.endpoint /= out.pixels, out.angular /= out.pixels, out.speed /= out.pixels;
  if (out.slow_pixels > 0) out.slow_endpoint /= out.slow_pixels, out.slow_speed /= out.slow_pixels;
  return out;
}

}  // namespace fluidtex

namespace fluidtex {

namespace {

using Row = MetricRow;  // NaN = not measured

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

/// The report shows the worst frame of at most this many bad frame ranges.
constexpr int kWorstImages = 6;

/// Text as HTML shows it literally.
std::string html_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '&')
      out += "&amp;";
    else if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '\'')
      out += "&#39;";
    else
      out += c;
  }
  return out;
}

/// A number for people (charts, the report's table): 6 significant digits.
std::string number(double v) {
  if (std::isinf(v)) return v > 0 ? "∞" : "−∞";
  if (!std::isfinite(v)) return "–";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

double get(const Row& row, const std::string& key) {
  for (const auto& [k, v] : row) {
    if (k == key) return v;
  }
  return std::nan("");
}

/// One metric against frame as an inline SVG line chart (several series).
std::string svg_chart(const std::string& title, const std::vector<Row>& rows, const std::vector<std::string>& keys,
                      const std::vector<std::string>& labels) {
  const double W = 560, H = 230, L = 56, R = 150, T = 24, B = 34;
  double x0 = 1e300, x1 = -1e300, y0 = 0.0, y1 = -1e300;
  for (const Row& r : rows) {
    const double f = get(r, "frame");
    for (const std::string& k : keys) {
      const double v = get(r, k);
      if (!std::isfinite(v)) continue;
      x0 = std::min(x0, f), x1 = std::max(x1, f);
      y0 = std::min(y0, v), y1 = std::max(y1, v);
    }
  }
  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << W << "' height='" << H
    << "' font-family='sans-serif' font-size='11'>";
  s << "<text x='" << L << "' y='14' font-weight='bold'>" << title << "</text>";
  if (!(x1 >= x0) || !(y1 > -1e300)) return s.str() + "<text x='60' y='100'>not measured</text></svg>";
  if (x1 == x0) x1 = x0 + 1;
  if (y1 <= y0) y1 = y0 + (y0 == 0.0 ? 1.0 : std::abs(y0) * 0.1);  // a flat series: a readable axis
  auto X = [&](double f) { return L + (f - x0) / (x1 - x0) * (W - L - R); };
  auto Y = [&](double v) { return H - B - (v - y0) / (y1 - y0) * (H - T - B); };
  s << "<rect x='" << L << "' y='" << T << "' width='" << W - L - R << "' height='" << H - T - B
    << "' fill='none' stroke='#999'/>";
  // Ticks at 1, 2 or 5 times a power of ten, about five on each axis, with
  // grid lines across the plot.
  auto step_for = [](double range) {
    const double raw = range / 5.0, power = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0})
      if (m * power >= raw) return m * power;
    return 10.0 * power;
  };
  const double ystep = step_for(y1 - y0), xstep = std::max(1.0, step_for(x1 - x0));
  for (double v = std::ceil(y0 / ystep) * ystep; v <= y1 + 1e-9 * ystep; v += ystep) {
    const double y = Y(v);
    s << "<line x1='" << L << "' x2='" << W - R << "' y1='" << y << "' y2='" << y << "' stroke='#e4e4e4'/>";
    s << "<text x='" << L - 4 << "' y='" << y + 4 << "' text-anchor='end'>" << number(std::abs(v) < 1e-12 ? 0.0 : v)
      << "</text>";
  }
  for (double f = std::ceil(x0 / xstep) * xstep; f <= x1 + 1e-9; f += xstep) {
    s << "<line x1='" << X(f) << "' x2='" << X(f) << "' y1='" << H - B << "' y2='" << H - B + 4
      << "' stroke='#999'/><text x='" << X(f) << "' y='" << H - B + 15 << "' text-anchor='middle'>" << number(f)
      << "</text>";
  }
  s << "<text x='" << W - R << "' y='" << H - 2 << "' text-anchor='end'>frame</text>";
  const char* colors[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2"};
  for (std::size_t k = 0; k < keys.size(); ++k) {
    std::string path;
    for (const Row& r : rows) {
      const double v = get(r, keys[k]);
      if (!std::isfinite(v)) continue;
      char buf[64];
      std::snprintf(buf, sizeof buf, "%s%.1f,%.1f", path.empty() ? "M" : " L", X(get(r, "frame")), Y(v));
      path += buf;
    }
    const char* color = colors[k % 7];
    s << "<path d='" << path << "' fill='none' stroke='" << color << "' stroke-width='1.5'/>";
    s << "<text x='" << W - R + 8 << "' y='" << T + 12 + 14 * k << "' fill='" << color << "'>" << labels[k]
      << "</text>";
  }
  return s.str() + "</svg>";
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

std::string png_data_uri(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  return "data:image/png;base64," + OIIO::Strutil::base64_encode(bytes.str());
}

/// Renders two frames measured (one camera, no shading, so that only the
/// texture moves) and compares their optical flow with the liquid's motion
/// between them (`motion`, from the velocity at t) projected to the image,
/// over pixels inside the surface in both renders (2 pixels away from its
/// silhouette).
FlowError flow_against_velocity(const FrameMesh& mesh, const TexturedFrame& at_t, const TexturedFrame& at_next,
                                const LiquidMotion& motion, const EvalOptions& options) {
  std::vector<Vec3> both = at_t.mesh.positions;
  both.insert(both.end(), at_next.mesh.positions.begin(), at_next.mesh.positions.end());
  RenderOptions o = options.render;
  o.width = options.flow_width;
  o.shade = false;
  o = framed(both, o);
  const RenderResult a = render(at_t.mesh, at_t.atlas, o);
  const RenderResult b = render(at_next.mesh, at_next.atlas, o);
  const int w = a.color.width, h = a.color.height;
  const SurfaceIndex velocity(mesh);  // the input frame: its velocities
  Image expected;
  expected.width = w, expected.height = h, expected.channels = 2;
  expected.pixels.assign(static_cast<std::size_t>(w) * h * 2, 0.0f);
  std::vector<char> mask(static_cast<std::size_t>(w) * h, 0);
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      bool inside = true;
      for (int dy = -2; dy <= 2 && inside; ++dy) {
        for (int dx = -2; dx <= 2 && inside; ++dx) {
          const int xx = std::clamp(x + dx, 0, w - 1), yy = std::clamp(y + dy, 0, h - 1);
          inside = a.gbuffer.face_at(xx, yy) >= 0 && b.gbuffer.face_at(xx, yy) >= 0;
        }
      }
      if (!inside) continue;
      const Tri& t = at_t.mesh.triangles[a.gbuffer.face_at(x, y)];
      const Vec3& l = a.gbuffer.bary_at(x, y);
      const Vec3 p = interpolate(at_t.mesh.positions, t, l);
      const SurfacePoint s = velocity.closest_point(p);
      if (!s.valid()) continue;
      const Vec2 d = a.camera.image_displacement(p, motion.carry(p, velocity.velocity_at(s)) - p);
      const std::size_t i = texel_index(x, y, w);
      expected.pixels[2 * i] = static_cast<float>(d.x());
      expected.pixels[2 * i + 1] = static_cast<float>(d.y());
      mask[i] = 1;
    }
  });
  return optical_flow_error(a.color, b.color, expected, mask, options.flow_max_motion);
}

}  // namespace

namespace {

/// Patch life over the frames: births, deaths, recuts, lifetimes, churn and
/// the removal histogram (rule × age), from consecutive state files.
struct PatchHistory {
  std::map<std::uint32_t, int> born;                                         // live patch id -> first frame seen
  std::vector<double> lifetimes;                                             // frames lived by patches that died
  std::array<std::array<int, kAgeBuckets>, kRetireCauses> retired_by_age{};  // rule x age at removal
  std::set<std::uint32_t> previous_ids;
  bool have_previous = false;
  int previous_frame = 0;

  void add(int frame, const Tracker& tracker, Row& row) {
    const std::vector<Patch>& patches = tracker.patches();
    const PatchCounts counts = count_states(patches);
    row.emplace_back("patches", static_cast<double>(patches.size()));
    row.emplace_back("fading_in", counts.fading_in);
    row.emplace_back("active", counts.active);
    row.emplace_back("fading_out_distorted", counts.fading_out_distorted);
    row.emplace_back("fading_out_close", counts.fading_out_close);
    std::set<std::uint32_t> ids;
    int births = 0, recuts = 0;
    for (const Patch& p : patches) {
      ids.insert(p.id);
      if (!previous_ids.count(p.id)) ++births, born.emplace(p.id, frame);
      recuts += p.recut_frame == frame;
    }
    int deaths = 0;
    for (std::uint32_t id : previous_ids) {
      if (ids.count(id)) continue;
      ++deaths;
      lifetimes.push_back(frame - born[id]);
      born.erase(id);
    }
    row.emplace_back("births", have_previous ? births : std::nan(""));
    row.emplace_back("deaths", have_previous ? deaths : std::nan(""));
    row.emplace_back("recuts", have_previous ? recuts : std::nan(""));  // cut again in place (--distorted recut)
    // Churn: births per frame over live patches (a stepped run's pair spans
    // its step), and the share of patches active.
    row.emplace_back("birth_rate", have_previous && !patches.empty()
                                       ? births / static_cast<double>(patches.size()) / (frame - previous_frame)
                                       : std::nan(""));
    row.emplace_back("active_share",
                     patches.empty() ? std::nan("") : counts.active / static_cast<double>(patches.size()));
    if (have_previous) {
      for (auto& kv : retired_counts(tracker.retired())) row.push_back(std::move(kv));
      for (const RetiredPatch& r : tracker.retired()) ++retired_by_age[static_cast<int>(r.cause)][age_bucket(r.age)];
    }
    previous_ids = std::move(ids);
    have_previous = true;
    previous_frame = frame;
  }

  /// Patches still alive at the end count with their (censored) age.
  void finish(int last_frame) {
    for (const auto& [id, first] : born) lifetimes.push_back(last_frame - first + 1);
  }
};

/// Where the patches are against where the liquid makes and destroys
/// surface (surface_change.h), from consecutive state files: per class of
/// change, the patches per area over the first frame's patches per area,
/// and the pair's births and removals there (a removed patch at its last
/// centre, on the new surface).
struct ChangeHistory {
  std::shared_ptr<const SurfaceIndex> surface;
  std::map<std::uint32_t, Vec3> centres;
  int frame = 0;
  double first_density = 0.0;

  void add(int next_frame, const Tracker& tracker, double fps, Row& row) {
    const std::shared_ptr<const SurfaceIndex> next = tracker.shared_surface();
    std::map<std::uint32_t, Vec3> now;
    for (const Patch& p : tracker.patches()) now.emplace(p.id, p.centre.point.position);
    if (first_density == 0.0 && next->area() > 0.0) first_density = static_cast<double>(now.size()) / next->area();
    if (surface && first_density > 0.0) {
      const TrackingOptions& o = tracker.settings().tracking;
      const int steps = next_frame - frame;
      const SurfaceChange change = measure_surface_change(*surface, *next, steps / fps, steps, o.d(), o.plane_angle);
      std::vector<SurfacePoint> at;
      for (const Patch& p : tracker.patches()) at.push_back(p.centre.point);
      std::vector<Vec3> births, removals;
      for (const auto& [id, x] : now)
        if (!centres.count(id)) births.push_back(x);
      for (const auto& [id, x] : centres)
        if (!now.count(id)) removals.push_back(x);
      const ChangeTally tally = tally_change(*next, change, at, births, removals);
      for (int c = 0; c < kChangeClasses; ++c) {
        const std::string name = change_class_name(c);
        row.emplace_back("density_" + name,
                         tally.area[c] > 0.0 ? tally.patches[c] / tally.area[c] / first_density : std::nan(""));
        row.emplace_back("births_" + name, tally.births[c]);
        row.emplace_back("removals_" + name, tally.removals[c]);
      }
      // The surface made per frame over the whole: at a constant patch
      // count per area, the least births per live patch a frame.
      row.emplace_back("surface_made", tally.made / next->area() / steps);
      row.emplace_back("surface_lost", tally.lost / next->area() / steps);
    }
    surface = next;
    centres = std::move(now);
    frame = next_frame;
  }
};

/// Coverage (surface area and texels with Σw = 0), ghosting (patches blended
/// per texel, re-synthesised with the count layer) and distortion of the
/// frame's patches.
void patch_metrics(const Tracker& tracker, const JobOptions& job, const Exemplar& exemplar, Row& row) {
  const TrackingOptions& o = tracker.settings().tracking;
  const std::vector<Patch>& patches = tracker.patches();
  const PatchCoverage coverage(patches, o.mpt());
  row.emplace_back("uncovered_area", uncovered_area_fraction(*tracker.surface(), coverage, tracker.coverage_spacing()));
  SynthesisOptions so = synthesis_options(o, job.synthesis);
  so.aov = true;
  const Atlas atlas = build_atlas(*tracker.surface(), job.synthesis.atlas);
  const TexelMap map = build_texel_map(*tracker.surface(), atlas);
  const SynthesisResult synth = synthesize(*tracker.surface(), atlas, map, patches, exemplar, so);
  row.emplace_back("uncovered_texels", synth.uncovered_fraction());
  std::vector<double> count;
  for (std::size_t t = 0; t < map.face.size(); ++t) {
    if (map.face[t] >= 0) count.push_back(synth.count.pixels[t]);
  }
  row.emplace_back("ghosting_mean",
                   count.empty() ? std::nan("") : std::accumulate(count.begin(), count.end(), 0.0) / count.size());
  row.emplace_back("ghosting_p95", quantile(count, 0.95));

  std::vector<double> distortion;
  std::size_t vertices = 0, poor = 0;
  for (const Patch& p : patches) {
    for (std::size_t t = 0; t < p.triangles.size(); ++t) {
      const Tri& tri = p.triangles[t];
      distortion.push_back(
          triangle_distortion(p.rest[t], p.positions[tri[0]], p.positions[tri[1]], p.positions[tri[2]]));
    }
    for (float q : p.quality) vertices++, poor += q < 0.5f;
  }
  row.emplace_back("distortion_median", quantile(distortion, 0.5));
  row.emplace_back("distortion_p95", quantile(distortion, 0.95));
  row.emplace_back("distortion_max",
                   distortion.empty() ? std::nan("") : *std::max_element(distortion.begin(), distortion.end()));
  row.emplace_back("quality_below_half", vertices ? static_cast<double>(poor) / vertices : std::nan(""));
}

/// Contrast and spectrum of the atlas the run wrote, against the exemplar at
/// the atlas's texel density.
void texture_metrics(const TexturedFrame& frame, const TrackingOptions& resolved, const Exemplar& exemplar, Row& row) {
  const std::vector<char> mask = chart_mask(frame.mesh, frame.atlas.width);
  const std::vector<double> contrast = contrast_ratio(frame.atlas, mask, exemplar);
  const char* channel[] = {"contrast_r", "contrast_g", "contrast_b"};
  for (std::size_t c = 0; c < contrast.size(); ++c)
    row.emplace_back(contrast.size() == 1 ? "contrast" : channel[c], contrast[c]);
  const double tile = resolved.exemplar_tile_size();
  const double density = texel_density(frame.mesh, frame.atlas.width);
  const double scale =
      exemplar.image().width * resolved.uv_scale / (tile * density);  // exemplar texels per atlas texel
  double spectrum = std::nan("");
  for (int n : {64, 32, 16}) {
    // 64 windows a frame and 32 exemplar crops: with 8 of each a frame's
    // figure depends on which 8 places of the surface the chart layout
    // puts first in scan order.
    const auto windows = chart_windows(mask, frame.atlas.width, n, 64);
    if (windows.empty() || !(scale > 0.0)) continue;
    std::vector<double> reference(n / 2 - 1, 0.0);
    const int crops = 32;
    for (int k = 0; k < crops; ++k) {
      const Image crop =
          exemplar_crop(exemplar, exemplar.image().width * (0.37 * k), exemplar.image().height * (0.61 * k), scale, n);
      const std::vector<double> s = radial_log_spectrum(crop, 0, 0, n);
      for (std::size_t b = 0; b < s.size(); ++b) reference[b] += s[b] / crops;
    }
    double sum = 0.0;
    for (const auto& [x, y] : windows) sum += spectrum_distance(radial_log_spectrum(frame.atlas, x, y, n), reference);
    spectrum = sum / static_cast<double>(windows.size());
    row.emplace_back("spectrum_crop", n);
    break;
  }
  row.emplace_back("spectrum_distance", spectrum);
}

/// Texture–flow agreement of two frames measured: warping error and optical
/// flow against the liquid's projected motion.
void flow_metrics(const FrameMesh& previous_mesh, const TexturedFrame& previous, const TexturedFrame& current,
                  const LiquidMotion& motion, const Exemplar& exemplar, const EvalOptions& options, int frame,
                  Row& row) {
  const WarpingError w =
      warping_error(previous_mesh, previous, current, motion, exemplar, options.samples, options.seed + frame);
  row.emplace_back("warp_advected", w.advected);
  row.emplace_back("warp_fixed", w.fixed);
  row.emplace_back("warp_random", w.random);
  if (options.flow_width > 0) {
    const FlowError f = flow_against_velocity(previous_mesh, previous, current, motion, options);
    row.emplace_back("flow_endpoint_px", f.pixels ? f.endpoint : std::nan(""));
    row.emplace_back("flow_angular_deg", f.pixels ? f.angular : std::nan(""));
    row.emplace_back("flow_speed_px", f.pixels ? f.speed : std::nan(""));
    row.emplace_back("flow_slow_endpoint_px", f.slow_pixels ? f.slow_endpoint : std::nan(""));
    row.emplace_back("flow_slow_speed_px", f.slow_pixels ? f.slow_speed : std::nan(""));
    row.emplace_back("flow_slow_share", f.pixels ? static_cast<double>(f.slow_pixels) / f.pixels : std::nan(""));
  }
}

/// Means over the frames measured of every key, and the mean patch lifetime.
Row summarize(const std::vector<Row>& rows, const std::vector<double>& lifetimes) {
  Row summary{{"frames", static_cast<double>(rows.size())}};
  std::vector<std::string> keys;
  for (const Row& r : rows) {
    for (const auto& [k, v] : r) {
      if (k != "frame" && k != "spectrum_crop" && std::find(keys.begin(), keys.end(), k) == keys.end())
        keys.push_back(k);
    }
  }
  for (const std::string& k : keys) {
    double sum = 0.0;
    int n = 0;
    for (const Row& r : rows) {
      const double v = get(r, k);
      if (std::isfinite(v)) sum += v, ++n;
    }
    summary.emplace_back(k == "uncovered_area" || k == "uncovered_texels" ? k + "_mean" : k,
                         n ? sum / n : std::nan(""));
  }
  summary.emplace_back(
      "patch_lifetime_mean",
      lifetimes.empty() ? std::nan("") : std::accumulate(lifetimes.begin(), lifetimes.end(), 0.0) / lifetimes.size());
  return summary;
}

/// The report's verdict: the figures with their grades and bounds, the
/// frame ranges where one is bad, and their worst frames.
std::string html_verdict(const Verdict& verdict, const std::vector<std::string>& worst_images) {
  std::ostringstream html;
  const char* color[] = {"#2ca02c", "#e6a100", "#d62728"};
  html << "<h2>Verdict: <span style='color:" << color[static_cast<int>(verdict.grade)] << "'>"
       << enum_name(verdict.grade) << "</span></h2><p>" << html_escape(verdict.line)
       << "</p><table><tr><th>figure</th><th>value</th><th>grade</th><th style='text-align:left'>unit</th>"
          "<th>good up to</th><th>bad above</th><th style='text-align:left'>when bad</th></tr>";
  for (const VerdictFigure& f : verdict.figures) {
    html << "<tr><th>" << f.name << "</th><td>" << number(f.value)
         << "</td><td style='color:" << (std::isnan(f.value) ? "#888" : color[static_cast<int>(f.grade)]) << "'>"
         << (std::isnan(f.value) ? "not measured" : enum_name(f.grade)) << "</td><td style='text-align:left'>"
         << html_escape(f.unit) << "</td><td>" << number(f.good) << "</td><td>" << number(f.bad)
         << "</td><td style='text-align:left'>" << html_escape(f.meaning) << "</td></tr>";
  }
  html << "</table>";
  if (!verdict.ranges.empty()) {
    html << "<h3>Where it is bad</h3><ul>";
    for (std::size_t i = 0; i < verdict.ranges.size(); ++i) {
      html << "<li>" << html_escape(verdict.ranges[i].line);
      if (i < worst_images.size())
        html << " &mdash; <a href='#worst" << i << "'>frame " << verdict.ranges[i].worst << "</a>";
      html << "</li>";
    }
    html << "</ul>";
    for (std::size_t i = 0; i < worst_images.size(); ++i) {
      html << "<figure id='worst" << i << "'><img src='" << png_data_uri(worst_images[i]) << "'><figcaption>frame "
           << verdict.ranges[i].worst << ": " << html_escape(verdict.ranges[i].line) << "</figcaption></figure>";
    }
  }
  return html.str();
}

/// The report's table of why patches leave: per rule, the patches it
/// retired by age bucket.
std::string html_retire_table(const PatchHistory& history) {
  std::ostringstream html;
  html << "<h2>Why patches leave</h2><p>Patches flagged to fade out or lost, by the rule that fired "
          "and their age then (frames since creation), over all frames.</p><table><tr><th>rule</th>";
  for (int b = 0; b < kAgeBuckets; ++b) {
    std::string name = age_bucket_name(b);
    std::replace(name.begin(), name.end(), '_', '-');
    html << "<th>age " << (b == kAgeBuckets - 1 ? "32+" : name) << "</th>";
  }
  html << "<th>all</th></tr>";
  for (int c = 1; c < kRetireCauses; ++c) {
    html << "<tr><th>" << to_string(static_cast<RetireCause>(c)) << "</th>";
    int total = 0;
    for (int n : history.retired_by_age[c]) html << "<td>" << n << "</td>", total += n;
    html << "<td>" << total << "</td></tr>";
  }
  html << "</table>";
  return html.str();
}

/// The report's charts: title, the row keys drawn, their legends.
using Chart = std::tuple<std::string, std::vector<std::string>, std::vector<std::string>>;
const std::vector<Chart>& report_charts() {
  static const std::vector<Chart> charts = {
      {"Coverage: uncovered share (should be 0)",
       {"uncovered_area", "uncovered_texels"},
       {"surface area", "chart texels"}},
      {"Ghosting: patches blended per texel", {"ghosting_mean", "ghosting_p95"}, {"mean", "95th pct"}},
      {"Patches by state",
       {"active", "fading_in", "fading_out_distorted", "fading_out_close"},
       {"active", "fading in", "out: distorted", "out: too close"}},
      {"Patch births, deaths and recuts", {"births", "deaths", "recuts"}, {"births", "deaths", "cut again in place"}},
      {"Churn: births per frame over live patches, active share",
       {"birth_rate", "active_share"},
       {"births / frame / live", "active / live"}},
      {"Patches retired per frame, by rule",
       {"retired_centre_lost", "retired_emptied", "retired_vertices_lost", "retired_split", "retired_flipped",
        "retired_quality", "retired_too_close"},
       {"centre lost", "emptied", "vertices lost", "split", "flipped", "quality", "too close"}},
      {"Patches per area where surface is destroyed, kept and made (over the first frame's)",
       {"density_sink_fast", "density_sink", "density_kept", "density_source", "density_source_fast"},
       {"shrinking > 5 %/frame", "shrinking 1-5 %", "kept (±1 %)", "growing 1-5 %", "growing > 5 %/frame"}},
      {"Births by surface change",
       {"births_sink_fast", "births_sink", "births_kept", "births_source", "births_source_fast"},
       {"shrinking > 5 %/frame", "shrinking 1-5 %", "kept (±1 %)", "growing 1-5 %", "growing > 5 %/frame"}},
      {"Removals by surface change",
       {"removals_sink_fast", "removals_sink", "removals_kept", "removals_source", "removals_source_fast"},
       {"shrinking > 5 %/frame", "shrinking 1-5 %", "kept (±1 %)", "growing 1-5 %", "growing > 5 %/frame"}},
      {"Distortion D_T", {"distortion_median", "distortion_p95"}, {"median", "95th pct"}},
      {"Warping error (σ units)", {"warp_advected", "warp_fixed", "warp_random"}, {"advected", "not moving", "random"}},
      {"Optical flow vs projected velocity (px)",
       {"flow_endpoint_px", "flow_speed_px", "flow_slow_endpoint_px", "flow_slow_speed_px"},
       {"endpoint error", "|velocity| (static)", "endpoint error, slow pixels", "|velocity|, slow pixels"}},
      {"Optical flow angular error (deg)", {"flow_angular_deg"}, {"angular"}},
      {"Contrast σ_out / σ_exemplar", {"contrast_r", "contrast_g", "contrast_b", "contrast"}, {"R", "G", "B", "grey"}},
      {"Spectrum distance to the exemplar", {"spectrum_distance"}, {"log-spectrum RMS"}},
  };
  return charts;
}

/// The self-contained HTML report: summary, removal table, charts, frames.
std::string html_report(const std::string& run_dir, const std::vector<Row>& rows, const Row& summary,
                        const PatchHistory& history, const std::vector<std::string>& images, const Verdict& verdict,
                        const std::vector<std::string>& worst_images) {
  std::ostringstream html;
  html << "<!DOCTYPE html><html><head><meta charset='utf-8'><title>fluidtex eval: " << run_dir
       << "</title><style>body{font-family:sans-serif;margin:24px;max-width:1200px}td,th{padding:2px "
          "10px;text-align:right}"
          "th{text-align:left}figure{display:inline-block;margin:6px}img{max-width:280px}</style></head><body>";
  html << "<h1>fluidtex eval</h1><p>Run: <code>" << run_dir << "</code>, " << rows.size()
       << " frames. Warping error is the mean colour change along the flow between consecutive frames in units of the "
          "exemplar's σ; a texture that moves with the fluid stays far below both baselines (a texture that does not "
          "move, and random points).</p>";
  html << html_verdict(verdict, worst_images);
  html << "<h2>Summary</h2><p>Means over the frames measured (metrics.jsonl has every frame).</p><table>";
  for (const auto& [k, v] : summary) html << "<tr><th>" << k << "</th><td>" << number(v) << "</td></tr>";
  html << "</table>" << html_retire_table(history);
  html << "<h2>Per frame</h2>";
  for (const auto& [title, ks, labels] : report_charts()) html << svg_chart(title, rows, ks, labels) << "\n";
  html << "<h2>Frames</h2>";
  for (const std::string& png : images) {
    html << "<figure><img src='" << png_data_uri(png) << "'><figcaption>"
         << std::filesystem::path(png).filename().string() << "</figcaption></figure>";
  }
  html << "</body></html>\n";
  return html.str();
}

}  // namespace

TexturedFrame read_run_frame(const std::string& atlas_pattern, const std::string& mesh_pattern, int frame) {
  const std::string atlas_path = FramePattern(atlas_pattern).path(frame);
  const std::string mesh_path = FramePattern(mesh_pattern).path(frame);
  if (!std::filesystem::exists(atlas_path))
    throw InputError(atlas_path, "missing: the run has no atlas for frame " + std::to_string(frame));
  if (!std::filesystem::exists(mesh_path))
    throw InputError(mesh_path, "missing: the run has no UV mesh for frame " + std::to_string(frame));
  Image atlas = read_image(atlas_path, kMaxAtlasPixels);
  // Colours are looked up into fixed buffers of kMaxLookupChannels.
  if (atlas.channels > kMaxLookupChannels) {
    throw InputError(atlas_path, std::to_string(atlas.channels) + " channels (a fluidtex atlas has at most " +
                                     std::to_string(kMaxLookupChannels) + ")");
  }
  return TexturedFrame(read_uv_mesh(mesh_path), std::move(atlas));
}

namespace {

/// The worst frame of each range where a figure is bad (at most
/// kWorstImages), rendered to DIR/worst.####.png for the report.
std::vector<std::string> render_worst_frames(const Verdict& verdict, const std::string& atlas_pattern,
                                             const std::string& mesh_pattern, const std::string& dir,
                                             const RenderOptions& render) {
  std::vector<std::string> images;
  for (const VerdictRange& r : verdict.ranges) {
    if (static_cast<int>(images.size()) == kWorstImages) break;
    const std::string png = FramePattern(dir + "/worst.####.png").path(r.worst);
    const TexturedFrame frame = read_run_frame(atlas_pattern, mesh_pattern, r.worst);
    write_image(png, render_textured(frame.mesh, frame.atlas, render), ImageWriteOptions{});
    images.push_back(png);
  }
  return images;
}

}  // namespace

namespace {

/// The frames a sequence is read from: its own and those on disk between
/// them (followed), and the liquid's motion from one frame to another
/// through them.
class FollowedFrames {
 public:
  explicit FollowedFrames(const Sequence& sequence) : read_(sequence.followed()) {}

  std::shared_ptr<const FrameMesh> mesh(int frame) const {
    return load(std::lower_bound(read_.frames().begin(), read_.frames().end(), frame));
  }

  LiquidMotion motion_between(int from, int to) const {
    const std::vector<int>& followed = read_.frames();
    const auto first = std::upper_bound(followed.begin(), followed.end(), from);
    const auto last = std::lower_bound(first, followed.end(), to);
    LiquidMotion motion((first == last ? to - from : *first - from) / read_.fps());
    for (auto it = first; it != last; ++it) {
      const int next = it + 1 == last ? to : *(it + 1);
      motion.add_step(load(it), (next - *it) / read_.fps());
    }
    return motion;
  }

 private:
  std::shared_ptr<const FrameMesh> load(std::vector<int>::const_iterator at) const {
    return std::make_shared<const FrameMesh>(read_.load(static_cast<std::size_t>(at - read_.frames().begin())));
  }

  Sequence read_;
};

/// OUT/eval/: per-frame lines, a summary (means over the frames measured),
/// the verdict and the report (with the worst frames rendered).
EvalSummary write_eval_outputs(const EvalOptions& options, const std::string& atlas_pattern,
                               const std::string& mesh_pattern, const std::vector<Row>& rows,
                               const PatchHistory& history, const std::vector<std::string>& images) {
  const std::string dir = options.run_dir + "/eval";
  std::string lines;
  for (const Row& r : rows) lines += to_json_object(r) + "\n";
  write_text_atomically(dir + "/metrics.jsonl", lines);
  const Row summary = summarize(rows, history.lifetimes);
  write_text_atomically(dir + "/summary.json", to_json_object(summary) + "\n");
  EvalSummary out{rows.size(), dir + "/report.html", judge(rows, options.thresholds)};
  write_text_atomically(dir + "/verdict.json", verdict_json(out.verdict));
  const std::vector<std::string> worst_images =
      render_worst_frames(out.verdict, atlas_pattern, mesh_pattern, dir, options.render);
  write_text_atomically(dir + "/report.html",
                        html_report(options.run_dir, rows, summary, history, images, out.verdict, worst_images));
  return out;
}

}  // namespace

EvalSummary run_eval(const EvalOptions& options, const JobOptions& job_in, Reporter& reporter) {
  JobOptions job = job_in;
  job.output.dir = options.run_dir;
  const std::string atlas_pattern = job.output.atlas(), mesh_pattern = job.output.mesh();
  // The frames on disk between two measured ones (a stepped run's skipped
  // frames, followed or not) carry the liquid from one to the next.
  InputOptions input = options.input;
  input.skipped_frames = SkippedFrames::Follow;
  const Sequence sequence(input);
  const FollowedFrames read(sequence);
  const Exemplar exemplar =
      load_exemplar(options.exemplar.empty() ? job.exemplar : options.exemplar, job.synthesis.displacement);
  const std::string dir = options.run_dir + "/eval";
  std::filesystem::create_directories(dir);

  // The run's resolved lengths: from a state file when there is one, else
  // resolved on the first frame as the run did.
  std::optional<TrackingOptions> resolved;
  std::vector<Row> rows;
  PatchHistory history;
  ChangeHistory change;
  std::optional<TexturedFrame> previous;
  std::shared_ptr<const FrameMesh> previous_mesh;
  std::vector<std::string> images;
  const int image_every = std::max<int>(1, static_cast<int>(sequence.size()) / std::max(1, options.report_images));
  for (std::size_t i = 0; i < sequence.size(); ++i) {
    const int frame = sequence.frames()[i];
    reporter.progress(i, sequence.size(), "eval");
    // Read among the frames between (velocities from positions are central
    // differences over them, as a run that follows them reads them).
    auto mesh = read.mesh(frame);
    TexturedFrame current = read_run_frame(atlas_pattern, mesh_pattern, frame);
    Row row{{"frame", frame}};
    const std::string state = state_path(options.run_dir, frame);
    if (std::filesystem::exists(state)) {
      const Tracker tracker = Tracker::load(state, mesh);
      if (!resolved) resolved = tracker.settings().tracking;
      history.add(frame, tracker, row);
      change.add(frame, tracker, sequence.fps(), row);
      patch_metrics(tracker, job, exemplar, row);
    }
    if (!resolved) resolved = job.tracking.resolved(bounding_box(*mesh).diagonal());
    texture_metrics(current, *resolved, exemplar, row);
    if (previous) {
      const LiquidMotion motion = read.motion_between(sequence.frames()[i - 1], frame);
      flow_metrics(*previous_mesh, *previous, current, motion, exemplar, options, frame, row);
    }
    if (static_cast<int>(i) % image_every == 0 && static_cast<int>(images.size()) < options.report_images) {
      const std::string png = FramePattern(dir + "/preview.####.png").path(frame);
      write_image(png, render_textured(current.mesh, current.atlas, options.render), ImageWriteOptions{});
      images.push_back(png);
    }
    rows.push_back(std::move(row));
    previous.emplace(std::move(current));
    previous_mesh = mesh;
  }
  history.finish(sequence.frames().back());
  EvalSummary out = write_eval_outputs(options, atlas_pattern, mesh_pattern, rows, history, images);
  reporter.progress(sequence.size(), sequence.size(), "eval");
  return out;
}

}  // namespace fluidtex
