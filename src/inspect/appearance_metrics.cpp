#include "fluidtex/inspect/appearance_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <oneapi/tbb/parallel_for.h>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "fluidtex/geometry/point_index.h"
#include "fluidtex/inspect/texture_metrics.h"
#include "fluidtex/util/check.h"
#include "fluidtex/util/random.h"

namespace fluidtex {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// The luminance of every texel of `image` (luminance_at), one channel.
Image luminance_image(const Image& image) {
  Image out = Image::blank(image.width, image.height, 1);
  for (std::size_t i = 0; i < out.pixels.size(); ++i) out.pixels[i] = luminance_at<float>(image, i);
  return out;
}

// ---------------------------------------------------------------------------
// Orientation: the structure tensor.

/// Half-width of the derivative-of-Gaussian filters (σ = 1 texel).
constexpr int kFilterRadius = 2;

/// The 5×5 derivative of a Gaussian of σ = 1 texel along x (or y), centred
/// on (0, 0) as OpenImageIO's convolve takes a kernel.
OIIO::ImageBuf derivative_kernel(bool along_x) {
  const int side = 2 * kFilterRadius + 1;
  OIIO::ImageSpec spec(side, side, 1, OIIO::TypeDesc::FLOAT);
  spec.x = spec.y = spec.full_x = spec.full_y = -kFilterRadius;
  OIIO::ImageBuf kernel(spec);
  for (int y = -kFilterRadius; y <= kFilterRadius; ++y) {
    for (int x = -kFilterRadius; x <= kFilterRadius; ++x) {
      const float v = static_cast<float>(-(along_x ? x : y) * std::exp(-0.5 * (x * x + y * y)));
      kernel.setpixel(x, y, &v);
    }
  }
  return kernel;
}

/// The luminance gradient of every texel of `image`.
struct Gradients {
  int width = 0;
  std::vector<float> gx, gy;
};

Gradients luminance_gradients(const Image& image) {
  Image lum = luminance_image(image);
  const OIIO::ImageBuf src(OIIO::ImageSpec(lum.width, lum.height, 1, OIIO::TypeDesc::FLOAT), lum.pixels.data());
  Gradients g{lum.width, std::vector<float>(lum.pixels.size()), std::vector<float>(lum.pixels.size())};
  for (bool along_x : {true, false}) {
    // normalize = false: a derivative kernel sums to 0.
    const OIIO::ImageBuf d = OIIO::ImageBufAlgo::convolve(src, derivative_kernel(along_x), false);
    FLUIDTEX_CHECK(!d.has_error());
    d.get_pixels(d.roi(), OIIO::TypeDesc::FLOAT, (along_x ? g.gx : g.gy).data());
  }
  return g;
}

/// The structure tensor of the n×n window at (x0, y0), summed over its
/// texels at least kFilterRadius from its edge, in (x right, y up).
Eigen::Matrix2d window_tensor(const Gradients& g, int x0, int y0, int n) {
  Eigen::Matrix2d j = Eigen::Matrix2d::Zero();
  Rect2i{x0, y0, x0 + n, y0 + n}.grown(-kFilterRadius).for_each([&](int x, int y) {
    const std::size_t i = texel_index(x, y, g.width);
    const Vec2 d(g.gx[i], -g.gy[i]);  // y up, as the image is seen
    j += d * d.transpose();
  });
  return j;
}

/// Whether the map `a` from atlas texels to frame coordinates keeps
/// directions readable: 2|det a| / |a|² >= 0.8, i.e. the surface faces the
/// frame's plane within about 60° (a similarity gives 1, a squash by 2
/// along one direction 0.8).
bool readable(const Eigen::Matrix2d& a) {
  const double norm2 = a.squaredNorm();
  return norm2 > 0.0 && 2.0 * std::abs(a.determinant()) / norm2 >= 0.8;
}

/// Adds window tensor `j` to `o`: its direction, and its weight when
/// `directed`: coherence · `energy`. Returns its coherence (0 for a flat
/// window).
double add_window(const Eigen::Matrix2d& j, double energy, bool directed, TextureOrientation& o) {
  const double trace = j.trace(), anisotropy = std::hypot(j(0, 0) - j(1, 1), 2.0 * j(0, 1));  // λ1 + λ2, λ1 − λ2
  const double coherence = trace > 0.0 ? anisotropy / trace : 0.0;
  // The dominant gradient's angle, then the features' (perpendicular), in [0, π).
  const double gradient = 0.5 * std::atan2(2.0 * j(0, 1), j(0, 0) - j(1, 1));
  o.angles.push_back(std::fmod(gradient + 1.5 * M_PI, M_PI));
  o.weights.push_back(directed ? coherence * energy : 0.0);
  return coherence;
}

}  // namespace

namespace {

/// A uv triangle in atlas texels (x right, y down) with its map from atlas
/// texel displacements (x right, y up) to frame coordinates.
struct Piece {
  std::array<Vec2, 3> corners;
  Vec2 centroid;
  double area;  ///< texels
  Eigen::Matrix2d map;

  bool contains(const Vec2& q) const {
    auto side = [&](int a, int b) {
      const Vec2 e = corners[b] - corners[a], f = q - corners[a];
      return e.x() * f.y() - e.y() * f.x();
    };
    const double s0 = side(0, 1), s1 = side(1, 2), s2 = side(2, 0);
    return (s0 >= 0.0 && s1 >= 0.0 && s2 >= 0.0) || (s0 <= 0.0 && s1 <= 0.0 && s2 <= 0.0);
  }
};

/// The pieces of `mesh`'s uv triangles of non-zero area in a `size`² atlas.
std::vector<Piece> uv_pieces(const UVMesh& mesh, int size, const DirectionFrame& frame) {
  std::vector<Piece> pieces;
  for (std::size_t t = 0; t < mesh.uv_triangles.size(); ++t) {
    Piece p;
    for (int k = 0; k < 3; ++k) {
      const Vec2& uv = mesh.uvs[mesh.uv_triangles[t][k]];
      p.corners[k] = Vec2(u_to_px(uv.x(), size), v_to_py(uv.y(), size));
    }
    Eigen::Matrix2d texels, plane;
    for (int k = 0; k < 2; ++k) {
      const Vec2 d = p.corners[k + 1] - p.corners[0];
      texels.col(k) = Vec2(d.x(), -d.y());  // y up
      const Vec3 e = mesh.positions[mesh.triangles[t][k + 1]] - mesh.positions[mesh.triangles[t][0]];
      plane.col(k) = Vec2(e.dot(frame.u), e.dot(frame.v));
    }
    const double det = texels.determinant();
    if (det == 0.0) continue;
    p.centroid = (p.corners[0] + p.corners[1] + p.corners[2]) / 3.0;
    p.area = 0.5 * std::abs(det);
    p.map = plane * texels.inverse();
    pieces.push_back(p);
  }
  return pieces;
}

}  // namespace

std::vector<Eigen::Matrix2d> window_frames(const UVMesh& mesh, int size,
                                           const std::vector<std::pair<int, int>>& corners, int n,
                                           const DirectionFrame& frame) {
  const std::vector<Piece> pieces = uv_pieces(mesh, size, frame);
  // The pieces by the cells of a grid of windows their texel boxes touch.
  const TileGrid grid{size, size, std::max(n, 8)};
  std::vector<std::vector<std::size_t>> cells(grid.count());
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const std::array<Vec2, 3>& c = pieces[i].corners;
    const Rect2i box = texel_box(c[0].cwiseMin(c[1]).cwiseMin(c[2]), c[0].cwiseMax(c[1]).cwiseMax(c[2]));
    grid.for_each_tile(box, [&](std::size_t cell) { cells[cell].push_back(i); });
  }
  std::vector<Eigen::Matrix2d> out;
  for (const auto& [x0, y0] : corners) {
    // The uv-area-weighted mean of the pieces centred in the window (each
    // counted in the cell of its centroid), or the piece holding its centre.
    const Rect2i window{x0, y0, x0 + n, y0 + n};
    const Vec2 centre(x0 + 0.5 * n, y0 + 0.5 * n);
    Eigen::Matrix2d sum = Eigen::Matrix2d::Zero(), holding = Eigen::Matrix2d::Zero();
    double area = 0.0;
    grid.for_each_tile(window, [&](std::size_t cell) {
      for (std::size_t i : cells[cell]) {
        const Piece& p = pieces[i];
        const int px = static_cast<int>(std::floor(p.centroid.x())), py = static_cast<int>(std::floor(p.centroid.y()));
        if (px < window.x0 || px >= window.x1 || py < window.y0 || py >= window.y1) continue;
        if (grid.index_of(px, py) == cell) sum += p.area * p.map, area += p.area;
      }
    });
    if (area > 0.0) {
      out.emplace_back(sum / area);
      continue;
    }
    const std::size_t at = grid.index_of(std::clamp(static_cast<int>(centre.x()), 0, size - 1),
                                         std::clamp(static_cast<int>(centre.y()), 0, size - 1));
    for (std::size_t i : cells[at]) {
      if (pieces[i].contains(centre)) holding = pieces[i].map;
    }
    out.push_back(holding);
  }
  return out;
}

namespace {

/// The rotation part of `map` (polar decomposition: the orthogonal factor,
/// a mirror included); the identity for a zero map.
Eigen::Matrix2d rotation_of(const Eigen::Matrix2d& map) {
  if (map.isZero()) return Eigen::Matrix2d::Identity();
  const Eigen::JacobiSVD<Eigen::Matrix2d> svd(map, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU() * svd.matrixV().transpose();
}

}  // namespace

Image surface_view(const Image& atlas, const Vec2& centre, const Eigen::Matrix2d& map, int n) {
  const Eigen::Matrix2d back = rotation_of(map).transpose();
  Image view = Image::blank(n, n, atlas.channels);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const Vec2 d = back * Vec2(i + 0.5 - 0.5 * n, 0.5 * n - j - 0.5);  // y up
      sample_bilinear(atlas, centre.x() + d.x(), centre.y() - d.y(), view.pixel(texel_index(i, j, n)));
    }
  }
  return view;
}

TextureOrientation texture_orientation(const Image& image, const std::vector<std::pair<int, int>>& corners, int n,
                                       const std::vector<Eigen::Matrix2d>& frames) {
  FLUIDTEX_CHECK(frames.empty() || frames.size() == corners.size());
  TextureOrientation o;
  if (corners.empty()) {
    o.coherence = kNaN;
    return o;
  }
  const Gradients g = luminance_gradients(image);
  const double texels = std::pow(std::max(0, n - 2 * kFilterRadius), 2);
  double sum = 0.0;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const auto [x, y] = corners[k];
    FLUIDTEX_CHECK(x >= 0 && y >= 0 && x + n <= image.width && y + n <= image.height);
    Eigen::Matrix2d j = window_tensor(g, x, y, n);
    const double energy = texels > 0.0 ? j.trace() / texels : 0.0;  // mean |∇L|² in the atlas
    const bool directed = frames.empty() || readable(frames[k]);
    if (!frames.empty() && directed) {
      // Gradients are covectors: ∇ in the frame = a⁻ᵀ ∇ in the atlas.
      const Eigen::Matrix2d inverse = frames[k].inverse();
      j = inverse.transpose() * j * inverse;
    }
    sum += add_window(j, energy, directed, o);
  }
  o.coherence = sum / static_cast<double>(corners.size());
  return o;
}

TextureOrientation exemplar_texture_orientation(const Exemplar& exemplar, double scale, int n, int crops) {
  FLUIDTEX_CHECK_GT(scale, 0.0);
  TextureOrientation all;
  double sum = 0.0;
  const int w = exemplar.image().width, h = exemplar.image().height;
  for (int k = 0; k < crops; ++k) {
    const TextureOrientation one =
        texture_orientation(exemplar_crop(exemplar, w * (0.37 * k), h * (0.61 * k), scale, n), {{0, 0}}, n);
    sum += one.coherence;
    all.angles.push_back(one.angles.front());
    all.weights.push_back(one.weights.front());
  }
  all.coherence = crops > 0 ? sum / crops : kNaN;
  return all;
}

std::vector<double> direction_histogram(const TextureOrientation& o, int bins, double reference) {
  FLUIDTEX_CHECK_GT(bins, 0);
  std::vector<double> h(static_cast<std::size_t>(bins), 0.0);
  double total = 0.0;
  for (std::size_t i = 0; i < o.angles.size(); ++i) {
    double t = std::fmod(o.angles[i] - reference, M_PI);
    if (t < 0.0) t += M_PI;
    const int bin = static_cast<int>(std::floor(t / M_PI * bins + 0.5)) % bins;  // bin 0 centred on `reference`
    h[static_cast<std::size_t>(bin)] += o.weights[i];
    total += o.weights[i];
  }
  if (total > 0.0) {
    for (double& v : h) v /= total;
  }
  return h;
}

double dominant_direction(const TextureOrientation& o) {
  double c = 0.0, s = 0.0;
  for (std::size_t i = 0; i < o.angles.size(); ++i) {
    c += o.weights[i] * std::cos(2.0 * o.angles[i]);
    s += o.weights[i] * std::sin(2.0 * o.angles[i]);
  }
  if (c == 0.0 && s == 0.0) return kNaN;
  const double angle = 0.5 * std::atan2(s, c);
  return angle < 0.0 ? angle + M_PI : angle;
}

double histogram_half_l1(const std::vector<double>& a, const std::vector<double>& b) {
  FLUIDTEX_CHECK_EQ(a.size(), b.size());
  double sum = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) sum += std::abs(a[k] - b[k]);
  return 0.5 * sum;
}

namespace {

/// The angle between two directions of [0, π), in degrees in [0, 90].
double direction_difference_deg(double a, double b) {
  const double d = std::fmod(std::abs(a - b), M_PI);
  return std::min(d, M_PI - d) * 180.0 / M_PI;
}

/// The windows of the orientation figures: one exemplar tile at `scale`
/// (16 .. 128 texels), halved down to 16 until some lie inside the charts.
std::pair<int, std::vector<std::pair<int, int>>> tile_windows(const std::vector<char>& mask, int size,
                                                              const Exemplar& exemplar, double scale) {
  int n = static_cast<int>(std::clamp(std::round(exemplar.image().width / scale), 16.0, 128.0));
  for (; n >= 16; n /= 2) {
    auto windows = chart_windows(mask, size, n, 64);
    if (!windows.empty()) return {n, std::move(windows)};
  }
  return {0, {}};
}

}  // namespace

OrientationFigures orientation_figures(const Image& atlas, const UVMesh& mesh, const std::vector<char>& mask,
                                       const Exemplar& exemplar, double scale, const DirectionFrame& frame) {
  OrientationFigures f{kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, 0};
  if (!(scale > 0.0)) return f;
  const auto [n, windows] = tile_windows(mask, atlas.width, exemplar, scale);
  if (windows.empty()) return f;
  const TextureOrientation shown =
      texture_orientation(atlas, windows, n, window_frames(mesh, atlas.width, windows, n, frame));
  const TextureOrientation expected = exemplar_texture_orientation(exemplar, scale, n);
  f.window = n;
  f.coherence = shown.coherence;
  f.exemplar_coherence = expected.coherence;
  f.coherence_ratio = expected.coherence > 0.0 ? shown.coherence / expected.coherence : kNaN;
  f.histogram_distance = histogram_half_l1(direction_histogram(shown), direction_histogram(expected));
  const double a = dominant_direction(shown), b = dominant_direction(expected);
  if (std::isnan(a) || std::isnan(b)) return f;
  f.aligned_histogram_distance =
      histogram_half_l1(direction_histogram(shown, 12, a), direction_histogram(expected, 12, b));
  f.angle_deg = direction_difference_deg(a, b);
  return f;
}

// ---------------------------------------------------------------------------
// Nearest-window energy (Kwatra et al. 2005).

namespace {

/// Windows as the columns of a matrix: luminance less the exemplar's mean
/// luminance (which keeps the distances' cancellation small).
using Windows = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic>;

/// The salt of the reference windows' positions and angles (fixed: the
/// same windows on every frame and run).
constexpr std::uint64_t kReferenceSalt = 0x7769'6e64'6f77;

/// The window × window window of `luma` (a one-channel exemplar) centred on
/// exemplar texel coordinates `centre`, `scale` exemplar texels per window
/// texel, turned by `angle`, into `out` (less `offset`).
void exemplar_window(const Exemplar& luma, const Vec2& centre, double scale, double angle, int window, float offset,
                     float* out) {
  const int w = luma.image().width, h = luma.image().height;
  const double c = std::cos(angle) * scale, s = std::sin(angle) * scale, half = 0.5 * window;
  for (int j = 0; j < window; ++j) {
    for (int i = 0; i < window; ++i) {
      const double dx = i + 0.5 - half, dy = j + 0.5 - half;
      const double x = centre.x() + c * dx - s * dy, y = centre.y() + s * dx + c * dy;
      float v = 0.0f;
      luma.sample(px_to_u(x, w), py_to_v(y, h), &v);
      out[texel_index(i, j, window)] = v - offset;
    }
  }
}

/// The exemplar windows searched: every rotation, centres on a grid over one
/// tile `stride` atlas texels apart (parallel over rows of the grid, each
/// writing its own columns).
Windows exemplar_bank(const Exemplar& luma, double scale, const WindowEnergyOptions& options) {
  const int w = luma.image().width, h = luma.image().height;
  const double tile_x = w / scale, tile_y = h / scale;  // atlas texels
  const double budget = static_cast<double>(options.max_exemplar_windows) / options.rotations;
  const int stride = std::max(1, static_cast<int>(std::ceil(std::sqrt(tile_x * tile_y / budget))));
  const int columns = std::max(1, static_cast<int>(std::ceil(tile_x / stride)));
  const int rows = std::max(1, static_cast<int>(std::ceil(tile_y / stride)));
  const int d = options.window * options.window;
  Windows bank(d, static_cast<Eigen::Index>(options.rotations) * rows * columns);
  const float offset = luma.mean()[0];
  tbb::parallel_for(0, options.rotations * rows, [&](int rr) {
    const int r = rr / rows, y = rr % rows;
    const double angle = 2.0 * M_PI * r / options.rotations;
    for (int x = 0; x < columns; ++x) {
      const Vec2 centre(x * stride * scale, y * stride * scale);
      exemplar_window(luma, centre, scale, angle, options.window, offset,
                      bank.col((static_cast<Eigen::Index>(r) * rows + y) * columns + x).data());
    }
  });
  return bank;
}

/// Per column of `queries`, the squared distance to the nearest column of
/// `bank`: blocks of the bank in parallel, each its own slot, reduced in
/// block order.
std::vector<double> nearest_distances(const Windows& queries, const Windows& bank) {
  constexpr Eigen::Index kBlock = 4096;
  const Eigen::Index blocks = (bank.cols() + kBlock - 1) / kBlock;
  const Eigen::VectorXf query_norms = queries.colwise().squaredNorm().transpose();
  std::vector<Eigen::VectorXf> nearest(static_cast<std::size_t>(blocks));
  tbb::parallel_for(Eigen::Index(0), blocks, [&](Eigen::Index b) {
    const Eigen::Index first = b * kBlock, count = std::min(kBlock, bank.cols() - first);
    const auto block = bank.middleCols(first, count);
    const Eigen::RowVectorXf block_norms = block.colwise().squaredNorm();
    Eigen::MatrixXf d = -2.0f * (queries.transpose() * block);
    d.colwise() += query_norms;
    d.rowwise() += block_norms;
    nearest[static_cast<std::size_t>(b)] = d.rowwise().minCoeff();
  });
  std::vector<double> out(static_cast<std::size_t>(queries.cols()), std::numeric_limits<double>::infinity());
  for (const Eigen::VectorXf& n : nearest) {
    for (Eigen::Index q = 0; q < n.size(); ++q)
      out[static_cast<std::size_t>(q)] = std::min(out[static_cast<std::size_t>(q)], std::max(0.0, double(n[q])));
  }
  return out;
}

/// The n×n window of `atlas` centred on texel coordinates `centre` as the
/// surface shows it (surface_view with the window's `map`): its luminance
/// less `offset`.
void atlas_window(const Image& atlas, const Vec2& centre, const Eigen::Matrix2d& map, int n, float offset, float* out) {
  const Image view = surface_view(atlas, centre, map, n);
  for (std::size_t i = 0; i < static_cast<std::size_t>(n) * n; ++i) out[i] = luminance_at<float>(view, i) - offset;
}

/// The n×n window of the exemplar as an atlas shows it and atlas_window
/// reads it back: the exemplar at `scale`, turned by `turn`, on a chart
/// turned by `chart` (its texels bilinear lookups of the exemplar), read
/// along the frame (bilinear lookups of the chart's texels).
void reference_window(const Exemplar& luma, const Vec2& centre, double scale, double turn, double chart, int n,
                      float offset, float* out) {
  const int side = static_cast<int>(std::ceil(n * M_SQRT2)) + 4;  // the turned window's reach, and a border
  Image texels = Image::blank(side, side, 1);
  exemplar_window(luma, centre, scale, turn + chart, side, 0.0f, texels.pixels.data());
  const double c = std::cos(chart), s = std::sin(chart), half = 0.5 * side;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double dx = i + 0.5 - 0.5 * n, dy = j + 0.5 - 0.5 * n;
      float v = 0.0f;
      sample_bilinear(texels, half + c * dx + s * dy, half - s * dx + c * dy, &v);
      out[texel_index(i, j, n)] = v - offset;
    }
  }
}

/// The atlas windows measured (at most options.samples inside the charts),
/// read along the frame, and as many reference windows of the exemplar at
/// fixed pseudo-random positions over the tile, turns and chart angles, as
/// the columns of one matrix: the atlas's first. Returns the number of
/// atlas windows.
Eigen::Index query_windows(const Image& atlas, const UVMesh& mesh, const std::vector<char>& mask, const Exemplar& luma,
                           double scale, const DirectionFrame& frame, const WindowEnergyOptions& options,
                           Windows& out) {
  const int n = options.window;
  // Windows of n√2 inside the charts, so that a turned n×n window reads
  // chart texels only.
  const int reach = static_cast<int>(std::ceil(n * M_SQRT2));
  const auto corners = chart_windows(mask, atlas.width, reach, options.samples);
  const std::vector<Eigen::Matrix2d> maps = window_frames(mesh, atlas.width, corners, reach, frame);
  const Eigen::Index atlas_count = static_cast<Eigen::Index>(corners.size());
  out.resize(n * n, atlas_count + options.samples);
  const float offset = luma.mean()[0];
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const Vec2 centre(corners[k].first + 0.5 * reach, corners[k].second + 0.5 * reach);
    atlas_window(atlas, centre, maps[k], n, offset, out.col(static_cast<Eigen::Index>(k)).data());
  }
  const int w = luma.image().width, h = luma.image().height;
  for (int k = 0; k < options.samples; ++k) {
    auto random = [&](int d) {
      return uniform(0, Stream::Evaluation, kReferenceSalt, static_cast<std::uint64_t>(k), d);
    };
    reference_window(luma, Vec2(w * random(0), h * random(1)), scale, 2.0 * M_PI * random(2), 2.0 * M_PI * random(3), n,
                     offset, out.col(atlas_count + k).data());
  }
  return atlas_count;
}

}  // namespace

double window_energy_ratio(const Image& atlas, const UVMesh& mesh, const std::vector<char>& mask,
                           const Exemplar& exemplar, double scale, const DirectionFrame& frame,
                           const WindowEnergyOptions& options) {
  FLUIDTEX_CHECK(options.window > 0 && options.samples > 0 && options.rotations > 0);
  if (!(scale > 0.0)) return kNaN;
  const Exemplar luma(luminance_image(exemplar.image()));
  Windows queries;
  const Eigen::Index atlas_count = query_windows(atlas, mesh, mask, luma, scale, frame, options, queries);
  if (atlas_count == 0) return kNaN;
  const std::vector<double> d = nearest_distances(queries, exemplar_bank(luma, scale, options));
  double shown = 0.0, own = 0.0;
  for (std::size_t k = 0; k < d.size(); ++k) (static_cast<Eigen::Index>(k) < atlas_count ? shown : own) += d[k];
  shown /= static_cast<double>(atlas_count);
  own /= options.samples;
  return own > 0.0 ? shown / own : kNaN;
}

// ---------------------------------------------------------------------------
// The colour distribution.

double wasserstein_1d(std::vector<double> a, std::vector<double> b) {
  if (a.empty() || b.empty()) return kNaN;
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  // The quantile functions are steps at i/n and j/m: walk their breaks in
  // order ((i+1)/n against (j+1)/m compared in integers).
  const std::uint64_t n = a.size(), m = b.size();
  std::uint64_t i = 0, j = 0;
  double t = 0.0, sum = 0.0;
  while (i < n && j < m) {
    const std::uint64_t next_a = (i + 1) * m, next_b = (j + 1) * n;  // both over n·m
    const double next = static_cast<double>(std::min(next_a, next_b)) / static_cast<double>(n * m);
    sum += (next - t) * std::abs(a[i] - b[j]);
    t = next;
    if (next_a <= next_b) ++i;
    if (next_b <= next_a) ++j;
  }
  return sum;
}

double value_histogram_distance(const Image& atlas, const std::vector<char>& mask, const Exemplar& exemplar,
                                double scale) {
  if (!(scale > 0.0)) return kNaN;
  // The chart texels, every k-th beyond 2^20 (the distribution is the same,
  // the sort's memory bounded).
  std::vector<std::size_t> texels;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (mask[i]) texels.push_back(i);
  }
  if (texels.empty()) return kNaN;
  const std::size_t step = std::max<std::size_t>(1, texels.size() >> 20);
  const int nc = std::min(atlas.channels, exemplar.channels());
  const std::vector<Image> tiles = exemplar_tiles(exemplar, scale);
  const std::vector<double> sigma = resampled_stddev(exemplar, scale);
  double sum = 0.0;
  int channels = 0;
  for (int c = 0; c < nc; ++c) {
    std::vector<double> shown, expected;
    for (std::size_t k = 0; k < texels.size(); k += step) shown.push_back(atlas.pixel(texels[k])[c]);
    for (const Image& tile : tiles) {
      for (std::size_t i = 0; i < tile.pixels.size(); i += tile.channels) expected.push_back(tile.pixels[i + c]);
    }
    if (!(sigma[c] > 0.0)) continue;  // a flat channel: no unit to measure in
    sum += wasserstein_1d(std::move(shown), std::move(expected)) / sigma[c];
    ++channels;
  }
  return channels ? sum / channels : kNaN;
}

// ---------------------------------------------------------------------------
// The patch layout: the autocorrelation at the patch spacing.

std::vector<int> nearest_others(const std::vector<Vec3>& points) {
  std::vector<int> nearest(points.size(), -1);
  if (points.size() < 2) return nearest;
  Eigen::AlignedBox3d box;
  for (const Vec3& p : points) box.extend(p);
  const double diagonal = box.diagonal().norm();
  const PointIndex index(points);
  // A first radius about the spacing of as many points spread over the
  // box, doubled until another point is in reach (every one is once the
  // radius passes the diagonal).
  const double start = diagonal > 0.0 ? diagonal / std::sqrt(static_cast<double>(points.size())) : 1.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (double r = start; nearest[i] < 0; r *= 2.0) {
      for (int j : index.within(points[i], r)) {  // ascending: of two as near, the lower index
        const double distance = (points[j] - points[i]).norm();
        if (static_cast<std::size_t>(j) != i && distance < best) best = distance, nearest[i] = j;
      }
    }
  }
  return nearest;
}

double mean_nearest_distance(const std::vector<Vec3>& points) {
  if (points.size() < 2) return kNaN;
  const std::vector<int> nearest = nearest_others(points);
  double sum = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) sum += (points[nearest[i]] - points[i]).norm();
  return sum / static_cast<double>(points.size());
}

namespace {

/// The texels [x0, x0 + n) × [y0, y0 + n) of a one-channel image.
struct LumaWindow {
  const Image* luma;
  int x0, y0;
};

/// μ and σ² of the windows' texels on the grid of pair origins (every
/// `stride`-th texel).
std::pair<double, double> window_moments(const std::vector<LumaWindow>& windows, int n, int stride) {
  double sum = 0.0, sum2 = 0.0;
  std::size_t count = 0;
  for (const LumaWindow& w : windows) {
    for (int y = w.y0; y < w.y0 + n; y += stride) {
      for (int x = w.x0; x < w.x0 + n; x += stride) {
        const double v = w.luma->pixels[texel_index(x, y, w.luma->width)];
        sum += v, sum2 += v * v, ++count;
      }
    }
  }
  const double mean = sum / static_cast<double>(count);
  return {mean, std::max(0.0, sum2 / static_cast<double>(count) - mean * mean)};
}

/// Per lag of `lags` (texels), over the pairs of window `w` whose first
/// texel lies on the origin grid and whose second (a bilinear lookup) in the
/// window: Σ (L(x) − μ)(L(x + δ) − μ) into sums[k], the pairs into
/// counts[k].
void window_products(const LumaWindow& w, int n, int stride, const std::vector<Vec2>& lags, double mean, double* sums,
                     double* counts) {
  const double last_x = w.x0 + n - 1, last_y = w.y0 + n - 1;
  for (std::size_t k = 0; k < lags.size(); ++k) {
    const Vec2& d = lags[k];
    for (int y = w.y0; y < w.y0 + n; y += stride) {
      const double ey = y + d.y();
      if (ey < w.y0 || ey > last_y) continue;
      for (int x = w.x0; x < w.x0 + n; x += stride) {
        const double ex = x + d.x();
        if (ex < w.x0 || ex > last_x) continue;
        float v = 0.0f;
        sample_bilinear(*w.luma, ex + 0.5, ey + 0.5, &v);
        sums[k] += (w.luma->pixels[texel_index(x, y, w.luma->width)] - mean) * (v - mean);
        counts[k] += 1.0;
      }
    }
  }
}

/// The lags of `length` texels in `directions` directions over [0, π),
/// components within 1e-9 of a whole texel snapped to it (cos(π/2) is not
/// 0 in floating point).
std::vector<Vec2> lag_vectors(double length, int directions) {
  std::vector<Vec2> lags;
  for (int k = 0; k < directions; ++k) {
    const double angle = M_PI * k / directions;
    Vec2 d = length * Vec2(std::cos(angle), std::sin(angle));
    for (int c = 0; c < 2; ++c) {
      if (std::abs(d[c] - std::round(d[c])) < 1e-9) d[c] = std::round(d[c]);
    }
    lags.push_back(d);
  }
  return lags;
}

/// The autocorrelation at `lag` over n×n `windows` (Autocorrelation): the
/// windows in parallel, each its own slot, summed in window order.
Autocorrelation window_autocorrelation(const std::vector<LumaWindow>& windows, int n, double lag,
                                       const AutocorrelationOptions& options) {
  const int directions = options.directions;
  Autocorrelation out{kNaN, std::vector<double>(static_cast<std::size_t>(directions), kNaN)};
  if (windows.empty() || n <= 0) return out;
  const double origins = static_cast<double>(windows.size()) * n * n;
  const int stride = std::max(1, static_cast<int>(std::ceil(std::sqrt(origins / options.max_origins))));
  const std::pair<double, double> moments = window_moments(windows, n, stride);
  const double mean = moments.first, variance = moments.second;  // named: a lambda captures them
  if (!(variance > 0.0)) return out;
  const std::vector<Vec2> lags = lag_vectors(lag, directions);
  const std::size_t slot = 2 * static_cast<std::size_t>(directions);  // sums, then counts
  std::vector<double> slots(windows.size() * slot, 0.0);
  tbb::parallel_for(std::size_t(0), windows.size(), [&](std::size_t i) {
    double* s = slots.data() + i * slot;
    window_products(windows[i], n, stride, lags, mean, s, s + directions);
  });
  double sum = 0.0;
  int counted = 0;
  for (int k = 0; k < directions; ++k) {
    double products = 0.0, pairs = 0.0;
    for (std::size_t i = 0; i < windows.size(); ++i)
      products += slots[i * slot + k], pairs += slots[i * slot + directions + k];
    if (pairs == 0.0) continue;
    out.by_direction[static_cast<std::size_t>(k)] = products / (pairs * variance);
    sum += out.by_direction[static_cast<std::size_t>(k)], ++counted;
  }
  if (counted > 0) out.mean = sum / counted;
  return out;
}

}  // namespace

Autocorrelation luminance_autocorrelation(const Image& image, const std::vector<std::pair<int, int>>& corners, int n,
                                          double lag, const AutocorrelationOptions& options) {
  FLUIDTEX_CHECK(options.directions > 0 && options.max_origins > 0);
  const Image luma = luminance_image(image);
  std::vector<LumaWindow> windows;
  for (const auto& [x, y] : corners) {
    FLUIDTEX_CHECK(x >= 0 && y >= 0 && x + n <= image.width && y + n <= image.height);
    windows.push_back({&luma, x, y});
  }
  return window_autocorrelation(windows, n, lag, options);
}

Autocorrelation exemplar_autocorrelation(const Exemplar& exemplar, double scale, int n, double lag,
                                         const AutocorrelationOptions& options) {
  FLUIDTEX_CHECK(options.directions > 0 && options.max_origins > 0);
  FLUIDTEX_CHECK_GT(scale, 0.0);
  const int w = exemplar.image().width, h = exemplar.image().height;
  std::vector<Image> crops(static_cast<std::size_t>(std::max(0, options.crops)));
  std::vector<LumaWindow> windows;
  for (std::size_t k = 0; k < crops.size(); ++k) {
    const double t = static_cast<double>(k);
    crops[k] = luminance_image(exemplar_crop(exemplar, w * (0.37 * t), h * (0.61 * t), scale, n));
    windows.push_back({&crops[k], 0, 0});
  }
  return window_autocorrelation(windows, n, lag, options);
}

LayoutFigures layout_figures(const Image& atlas, const std::vector<char>& mask, const Exemplar& exemplar, double scale,
                             double lag, const AutocorrelationOptions& options) {
  LayoutFigures f{lag, kNaN, kNaN, kNaN, 0};
  if (!(lag > 0.0) || !(scale > 0.0) || !std::isfinite(lag)) return f;
  for (double reach : {2.0, 1.5, 1.25}) {
    const int n = std::max(16, static_cast<int>(std::ceil(reach * lag)) + 2);
    if (n > atlas.width) continue;
    const auto windows = chart_windows(mask, atlas.width, n, options.windows);
    if (windows.empty()) continue;
    f.window = n;
    f.atlas = luminance_autocorrelation(atlas, windows, n, lag, options).mean;
    f.exemplar = exemplar_autocorrelation(exemplar, scale, n, lag, options).mean;
    f.excess = f.atlas - f.exemplar;
    return f;
  }
  return f;
}

std::vector<NeighbourPair> neighbour_pairs(const UVMesh& mesh, const SurfaceIndex& surface, int size,
                                           const std::vector<Vec3>& centres, double density, int n,
                                           const DirectionFrame& frame) {
  // Each centre in the atlas through the closest point of the mesh, and the
  // window of n texels around it.
  std::vector<Vec2> texels;
  std::vector<std::pair<int, int>> corners;
  for (const Vec3& c : centres) {
    const SurfacePoint s = surface.closest_point(c);
    const Vec2 uv = s.valid() ? Vec2(interpolate(mesh.uvs, mesh.uv_triangles[s.face], s.bary)) : Vec2(kNaN, kNaN);
    texels.emplace_back(u_to_px(uv.x(), size), v_to_py(uv.y(), size));
    const bool inside = texels.back().allFinite();
    corners.emplace_back(inside ? static_cast<int>(std::floor(texels.back().x() - 0.5 * n)) : 0,
                         inside ? static_cast<int>(std::floor(texels.back().y() - 0.5 * n)) : 0);
  }
  const std::vector<Eigen::Matrix2d> maps = window_frames(mesh, size, corners, n, frame);
  const std::vector<int> nearest = nearest_others(centres);
  std::vector<NeighbourPair> pairs;
  for (std::size_t i = 0; i < centres.size(); ++i) {
    const int j = nearest[i];
    // Each pair once: a mutual pair from its lower index.
    if (j < 0 || (nearest[j] == static_cast<int>(i) && j < static_cast<int>(i))) continue;
    if (!texels[i].allFinite() || !texels[j].allFinite()) continue;
    const Vec3 chord = centres[j] - centres[i];
    pairs.push_back({texels[i], texels[j], maps[i], maps[j], density * Vec2(chord.dot(frame.u), chord.dot(frame.v))});
  }
  return pairs;
}

namespace {

/// Whether the side² square of texels centred on texel coordinates
/// `centre` lies inside a `size`² atlas and wholly inside the charts.
bool square_inside(const std::vector<char>& mask, int size, const Vec2& centre, int side) {
  const double x = std::floor(centre.x() - 0.5 * side), y = std::floor(centre.y() - 0.5 * side);
  if (!(x >= 0.0 && y >= 0.0 && x + side <= size && y + side <= size)) return false;
  bool inside = true;
  Rect2i{static_cast<int>(x), static_cast<int>(y), static_cast<int>(x) + side, static_cast<int>(y) + side}.for_each(
      [&](int i, int j) { inside = inside && mask[texel_index(i, j, size)]; });
  return inside;
}

/// The luminance of `crop` into `out` (n² values).
void crop_luminance(const Image& crop, float* out) {
  for (std::size_t i = 0; i < crop.pixels.size() / crop.channels; ++i) out[i] = luminance_at<float>(crop, i);
}

/// The mean over the column pairs (2k, 2k + 1) of `views` of
/// Σ (a − μ)(b − μ) / (rows · σ²), μ and σ over every entry.
double pair_correlation(const Windows& views) {
  const Eigen::MatrixXd v = views.cast<double>();
  const Eigen::MatrixXd centred = v.array() - v.mean();
  const double variance = centred.squaredNorm() / static_cast<double>(centred.size());
  if (!(variance > 0.0)) return kNaN;
  double sum = 0.0;
  const Eigen::Index pairs = v.cols() / 2;
  for (Eigen::Index k = 0; k < pairs; ++k) sum += centred.col(2 * k).dot(centred.col(2 * k + 1));
  return sum / (static_cast<double>(pairs) * static_cast<double>(v.rows()) * variance);
}

}  // namespace

namespace {

/// Exemplar crop pairs per neighbour pair: the exemplar's correlation at a
/// displacement varies with where it is read; more places make the
/// reference steadier than the atlas's own read.
constexpr int kReferencesPerPair = 4;

/// The pairs of `pairs` neighbour_figures reads: both views' turned
/// squares inside the charts, both maps readable.
std::vector<const NeighbourPair*> readable_pairs(const std::vector<NeighbourPair>& pairs, const std::vector<char>& mask,
                                                 int size, int n) {
  const int reach = static_cast<int>(std::ceil(n * M_SQRT2)) + 2;  // a turned view's texels and their neighbours
  std::vector<const NeighbourPair*> read;
  for (const NeighbourPair& p : pairs) {
    if (readable(p.from_map) && readable(p.to_map) && square_inside(mask, size, p.from, reach) &&
        square_inside(mask, size, p.to, reach))
      read.push_back(&p);
  }
  return read;
}

/// Into columns `first`, `first` + 1 of `out`: the luminance of two n×n
/// crops of the exemplar at `scale`, the second `displacement` (atlas
/// texels, y up) from the first (exemplar_crop reads y down), the first at
/// the `index`-th of fixed positions spread over the tile.
void reference_pair(const Exemplar& exemplar, double scale, const Vec2& displacement, std::size_t index, int n,
                    Windows& out, Eigen::Index first) {
  const double t = static_cast<double>(index);
  const Vec2 at(exemplar.image().width * std::fmod(0.37 * t, 1.0), exemplar.image().height * std::fmod(0.61 * t, 1.0));
  crop_luminance(exemplar_crop(exemplar, at.x(), at.y(), scale, n), out.col(first).data());
  crop_luminance(
      exemplar_crop(exemplar, at.x() + displacement.x() * scale, at.y() - displacement.y() * scale, scale, n),
      out.col(first + 1).data());
}

}  // namespace

NeighbourFigures neighbour_figures(const Image& atlas, const std::vector<char>& mask, const Exemplar& exemplar,
                                   double scale, const std::vector<NeighbourPair>& pairs, int n) {
  NeighbourFigures f{kNaN, kNaN, kNaN, 0, n};
  if (!(scale > 0.0) || n <= 0) return f;
  const std::vector<const NeighbourPair*> read = readable_pairs(pairs, mask, atlas.width, n);
  if (read.empty()) return f;
  // Per pair k, its two views (columns 2k, 2k + 1) and kReferencesPerPair
  // pairs of exemplar crops its displacement apart: each pair its own
  // columns.
  const auto count = static_cast<Eigen::Index>(read.size());
  Windows views(n * n, 2 * count), crops(n * n, 2 * kReferencesPerPair * count);
  tbb::parallel_for(std::size_t(0), read.size(), [&](std::size_t k) {
    const NeighbourPair& p = *read[k];
    const auto c = static_cast<Eigen::Index>(k);
    atlas_window(atlas, p.from, p.from_map, n, 0.0f, views.col(2 * c).data());
    atlas_window(atlas, p.to, p.to_map, n, 0.0f, views.col(2 * c + 1).data());
    for (int r = 0; r < kReferencesPerPair; ++r) {
      const Eigen::Index index = kReferencesPerPair * c + r;
      reference_pair(exemplar, scale, p.displacement, static_cast<std::size_t>(index), n, crops, 2 * index);
    }
  });
  f.pairs = static_cast<int>(read.size());
  f.atlas = pair_correlation(views);
  f.exemplar = pair_correlation(crops);
  f.excess = f.atlas - f.exemplar;
  return f;
}

}  // namespace fluidtex
