#include "fluidtex/texture/exemplar.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <numeric>

#include <Eigen/Eigenvalues>

#include "fluidtex/io/image_io.h"
#include "fluidtex/util/error.h"

namespace fluidtex {

struct Exemplar::Lazy {
  std::once_flag once;
  std::unique_ptr<GaussianExemplar> gaussian;
};

Exemplar::Exemplar(Image image) : lazy_(std::make_shared<Lazy>()), image_(std::move(image)) {
  if (image_.width < 1 || image_.height < 1 || image_.channels < 1) throw InputError("", "empty exemplar image");
  channels_ = image_.channels >= 3 ? 3 : 1;
  const std::size_t n = static_cast<std::size_t>(image_.width) * image_.height;
  for (int c = 0; c < channels_; ++c) {
    double sum = 0.0, sum2 = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double v = image_.pixels[i * image_.channels + c];
      sum += v;
      sum2 += v * v;
    }
    const double mean = sum / static_cast<double>(n);
    mean_[c] = static_cast<float>(mean);
    stddev_[c] = static_cast<float>(std::sqrt(std::max(0.0, sum2 / static_cast<double>(n) - mean * mean)));
  }
}

Exemplar Exemplar::load(const std::string& path) {
  Image image = read_image(path);
  if (image.channels == 2) throw InputError(path, "exemplar has 2 channels (expected grey, RGB or RGBA)");
  for (float v : image.pixels) {
    if (!std::isfinite(v)) throw InputError(path, "exemplar has NaN or infinite pixels");
  }
  try {
    return Exemplar(std::move(image));
  } catch (const InputError& e) {
    throw InputError(path, e.problem());
  }
}

const GaussianExemplar& Exemplar::gaussian() const {
  std::call_once(lazy_->once, [&] { lazy_->gaussian = std::make_unique<GaussianExemplar>(*this); });
  return *lazy_->gaussian;
}

void Exemplar::sample(double u, double v, float* out) const {
  const int w = image_.width, h = image_.height;
  // Texel centres at (i + ½)/w; v up, rows down.
  const double x = u_to_px(u, w) - 0.5;
  const double y = v_to_py(v, h) - 0.5;
  double fx = std::floor(x), fy = std::floor(y);
  if (!std::isfinite(fx) || !std::isfinite(fy)) fx = fy = 0.0;  // cannot come from a finite uv of a sane scale
  // Far from the origin, wrap before converting to an integer (exact for
  // integers below 2^53; farther out only the precision of the lookup suffers).
  if (std::abs(fx) > 0x1p30) fx -= w * std::floor(fx / w);
  if (std::abs(fy) > 0x1p30) fy -= h * std::floor(fy / h);
  const double tx = x - fx, ty = y - fy;
  // |fx|, |fy| <= 2^30 here: int arithmetic (a 32-bit division is the
  // cheaper one).
  auto wrap = [](int i, int n) {
    const int r = i % n;
    return r < 0 ? r + n : r;
  };
  const int x0 = wrap(static_cast<int>(fx), w), x1 = x0 + 1 == w ? 0 : x0 + 1;
  const int y0 = wrap(static_cast<int>(fy), h), y1 = y0 + 1 == h ? 0 : y0 + 1;
  const float* p00 = image_.pixel(texel_index(x0, y0, w));
  const float* p10 = image_.pixel(texel_index(x1, y0, w));
  const float* p01 = image_.pixel(texel_index(x0, y1, w));
  const float* p11 = image_.pixel(texel_index(x1, y1, w));
  const float a = static_cast<float>((1 - tx) * (1 - ty)), b = static_cast<float>(tx * (1 - ty));
  const float c = static_cast<float>((1 - tx) * ty), d = static_cast<float>(tx * ty);
  for (int k = 0; k < channels_; ++k) out[k] = a * p00[k] + b * p10[k] + c * p01[k] + d * p11[k];
}

namespace {

/// Entries of each axis's tables.
constexpr int kTable = 4096;

/// Φ, the standard normal CDF.
double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

/// Φ⁻¹(q) for q in (0, 1): Abramowitz and Stegun 26.2.23 (error below
/// 4.5e-4), then two Newton steps on Φ.
double normal_quantile(double q) {
  const double tail = std::min(q, 1.0 - q);
  const double t = std::sqrt(-2.0 * std::log(tail));
  double x =
      t - (2.515517 + 0.802853 * t + 0.010328 * t * t) / (1.0 + 1.432788 * t + 0.189269 * t * t + 0.001308 * t * t * t);
  if (q < 0.5) x = -x;
  for (int i = 0; i < 2; ++i) {
    const double density = std::exp(-0.5 * x * x) / std::sqrt(2.0 * M_PI);
    x -= (normal_cdf(x) - q) / density;
  }
  return x;
}

/// The principal axes of the exemplar's colours: the eigenvectors of their
/// covariance, the largest variance first, each signed so that its largest
/// component is positive. One channel: the channel itself.
std::array<std::array<double, 3>, 3> principal_axes(const Exemplar& exemplar) {
  std::array<std::array<double, 3>, 3> axes{};
  if (exemplar.channels() == 1) {
    axes[0] = {1.0, 0.0, 0.0};
    return axes;
  }
  const Image& image = exemplar.image();
  const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Vector3d c;
    for (int k = 0; k < 3; ++k) c[k] = image.pixel(i)[k] - exemplar.mean()[k];
    covariance += c * c.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance / static_cast<double>(n));
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d axis = solver.eigenvectors().col(2 - k);
    Eigen::Index largest;
    axis.cwiseAbs().maxCoeff(&largest);
    if (axis[largest] < 0.0) axis = -axis;
    axes[k] = {axis[0], axis[1], axis[2]};
  }
  return axes;
}

/// The empirical CDF of `values` as (distinct value, quantile of its mean
/// rank) pairs, ascending in both.
std::vector<std::pair<double, double>> cdf_knots(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const auto n = static_cast<double>(values.size());
  std::vector<std::pair<double, double>> knots;
  for (std::size_t first = 0; first < values.size();) {
    std::size_t last = first;
    while (last + 1 < values.size() && values[last + 1] == values[first]) ++last;
    knots.emplace_back(values[first], (0.5 * static_cast<double>(first + last) + 0.5) / n);
    first = last + 1;
  }
  return knots;
}

/// The piecewise-linear function through `knots` (x ascending) at x,
/// clamped to its end values; `flip` reads the knots as (y, x).
double through(const std::vector<std::pair<double, double>>& knots, double x, bool flip) {
  const auto key = [flip](const std::pair<double, double>& k) { return flip ? k.second : k.first; };
  const auto value = [flip](const std::pair<double, double>& k) { return flip ? k.first : k.second; };
  if (!(x > key(knots.front()))) return value(knots.front());
  if (!(x < key(knots.back()))) return value(knots.back());
  const auto above = std::upper_bound(knots.begin(), knots.end(), x,
                                      [&](double v, const std::pair<double, double>& k) { return v < key(k); });
  const auto below = above - 1;
  const double t = (x - key(*below)) / (key(*above) - key(*below));
  return value(*below) + t * (value(*above) - value(*below));
}

}  // namespace

GaussianExemplar::GaussianExemplar(const Exemplar& exemplar) : channels_(exemplar.channels()) {
  const Image& image = exemplar.image();
  const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
  for (int c = 0; c < channels_; ++c) mean_[c] = exemplar.mean()[c];
  const std::array<std::array<double, 3>, 3> directions = principal_axes(exemplar);
  std::vector<double> values(n);
  for (int k = 0; k < channels_; ++k) {
    Axis& axis = axes_[k];
    axis.direction = directions[k];
    for (std::size_t i = 0; i < n; ++i) {
      double v = 0.0;
      for (int c = 0; c < channels_; ++c) v += axis.direction[c] * (image.pixel(i)[c] - mean_[c]);
      values[i] = v;
    }
    const std::vector<std::pair<double, double>> knots = cdf_knots(values);
    const double low = knots.front().first, high = knots.back().first;
    axis.forward = {low, high > low ? (kTable - 1) / (high - low) : 0.0, std::vector<float>(kTable)};
    axis.inverse = {-kRange, (kTable - 1) / (2.0 * kRange), std::vector<float>(kTable)};
    for (int j = 0; j < kTable; ++j) {
      const double x = low + (high - low) * j / (kTable - 1);
      axis.forward.values[j] = static_cast<float>(normal_quantile(through(knots, x, false)));
      const double g = kRange * (2.0 * j / (kTable - 1) - 1.0);
      axis.inverse.values[j] = static_cast<float>(through(knots, normal_cdf(g), true));
    }
  }
}

double GaussianExemplar::Table::at(double x) const {
  const double last = static_cast<double>(values.size() - 1);
  const double t = std::clamp((x - origin) * per_step, 0.0, last);
  const std::size_t below = std::min(static_cast<std::size_t>(t), values.size() - 2);
  const double f = t - static_cast<double>(below);
  return values[below] + f * (values[below + 1] - values[below]);
}

void GaussianExemplar::to_gaussian(const float* colour, double* g) const {
  for (int k = 0; k < channels_; ++k) {
    const Axis& axis = axes_[k];
    double v = 0.0;
    for (int c = 0; c < channels_; ++c) v += axis.direction[c] * (colour[c] - mean_[c]);
    g[k] = axis.forward.at(v);
  }
}

void GaussianExemplar::to_colour(const double* g, float* out) const {
  std::array<double, 3> along{};
  for (int k = 0; k < channels_; ++k) along[k] = axes_[k].inverse.at(g[k]);
  for (int c = 0; c < channels_; ++c) {
    double v = mean_[c];
    for (int k = 0; k < channels_; ++k) v += along[k] * axes_[k].direction[c];
    out[c] = static_cast<float>(v);
  }
}

}  // namespace fluidtex
