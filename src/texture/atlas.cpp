#include "fluidtex/texture/atlas.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <tuple>
#include <unordered_map>

#include <oneapi/tbb/parallel_for.h>
#include <Eigen/Eigenvalues>

#include "fluidtex/geometry/disk_region.h"
#include "fluidtex/geometry/parameterization.h"
#include "fluidtex/util/check.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/strings.h"

namespace fluidtex {

void AtlasOptions::validate() const {
  check_options(*this);
  if (!(normal_cone > -1.0 && normal_cone < 1.0)) throw InputError("", "chart normal cone must be in (-1, 1)");
  FLUIDTEX_CHECK(max_tiles >= 1 && max_tiles <= kMaxUdimTiles);
}

namespace {

/// A chart flattened in scene units, before packing.
struct FlatChart {
  std::vector<std::array<Vec2, 3>> corners;  // per face of the chart
  Vec2 min = Vec2::Zero(), max = Vec2::Zero();
  FlatOutline outline;  // what bounds it: the packer's profiles are made from it
};

/// Flattens one chart: LSCM over its faces, then principal-axis rotation so
/// that its bounding rectangle is tight. A single face, or a chart LSCM
/// cannot handle, is laid flat face by face (the caller splits it).
bool flatten_chart(const FrameMesh& mesh, const std::vector<int>& faces, FlatChart& out, double& stretch) {
  const DiskMesh disk = extract_faces(mesh, faces);
  std::vector<Vec2> uv;
  if (!flatten_lscm(disk, uv)) return false;
  // Principal axes of the uv points.
  Vec2 mean = Vec2::Zero();
  for (const Vec2& p : uv) mean += p;
  mean /= static_cast<double>(uv.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const Vec2& p : uv) cov += (p - mean) * (p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  Eigen::Matrix2d R = eig.eigenvectors().transpose();
  if (R.determinant() < 0) R.row(1) *= -1.0;  // a rotation, not a mirror
  out.corners.resize(faces.size());
  out.min = Vec2::Constant(std::numeric_limits<double>::infinity());
  out.max = -out.min;
  double weighted = 0.0, total = 0.0;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const Vec2 p = R * (uv[disk.triangles[i][k]] - mean);
      out.corners[i][k] = p;
      out.min = out.min.cwiseMin(p);
      out.max = out.max.cwiseMax(p);
    }
    const auto& c = out.corners[i];
    const double a_uv = 0.5 * std::abs((c[1] - c[0]).x() * (c[2] - c[0]).y() - (c[1] - c[0]).y() * (c[2] - c[0]).x());
    const Tri& t = disk.triangles[i];
    const double a3 = triangle_area(disk.positions, t);
    if (a3 > 0.0 && a_uv > 0.0) {
      weighted += a3 * std::max(a_uv / a3, a3 / a_uv);
      total += a3;
    }
  }
  stretch = total > 0.0 ? weighted / total : 1.0;  // area-weighted mean
  out.outline = flat_outline(disk.triangles, out.corners);
  return true;
}

/// Share of the chart's bounding box its faces cover (the best a packer
/// can do with it).
double box_fill(const FlatChart& fc) {
  const Vec2 span = fc.max - fc.min;
  if (!(span.x() > 0.0 && span.y() > 0.0)) return 1.0;
  double area = 0.0;
  for (const auto& c : fc.corners) {
    area += 0.5 * std::abs((c[1] - c[0]).x() * (c[2] - c[0]).y() - (c[1] - c[0]).y() * (c[2] - c[0]).x());
  }
  return area / (span.x() * span.y());
}

/// One face laid flat on its own (for charts LSCM could not handle).
FlatChart flat_face(const FrameMesh& mesh, int f) {
  const Tri& t = mesh.triangles[f];
  const Vec3 a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
  const Vec3 x = (b - a).normalized();
  const Vec3 n = (b - a).cross(c - a);
  const Vec3 y = n.norm() > 0 ? Vec3(n.cross(x).normalized()) : Vec3::Zero();
  FlatChart out;
  out.corners = {{Vec2(0, 0), Vec2((b - a).norm(), 0), Vec2((c - a).dot(x), (c - a).dot(y))}};
  out.min = out.corners[0][0].cwiseMin(out.corners[0][1]).cwiseMin(out.corners[0][2]);
  out.max = out.corners[0][0].cwiseMax(out.corners[0][1]).cwiseMax(out.corners[0][2]);
  out.outline.loose_faces = {0};
  return out;
}

/// A chart's placement: its tile, rotation by r·90°, and the lower-left
/// texel of its footprint's box (gutter included).
struct Placement {
  int tile = 0;
  int rotation = 0;
  Eigen::Vector2i origin{0, 0};
  Eigen::Vector2i extent{0, 0};
};

/// Flat coordinates turned by r·90° and moved so that the box starts at 0.
Vec2 turn(const FlatChart& fc, int r, const Vec2& p) {
  switch (r) {
    case 1: return {fc.max.y() - p.y(), p.x() - fc.min.x()};
    case 2: return {fc.max.x() - p.x(), fc.max.y() - p.y()};
    case 3: return {p.y() - fc.min.y(), fc.max.x() - p.x()};
    default: return p - fc.min;
  }
}

/// Per column of `cell` texels, the cells a chart occupies (its footprint
/// grown by the gutter): [bottom, top); empty columns have bottom > top.
struct Profile {
  std::vector<int> bottom, top;
  int top_max = 0;
  Eigen::Vector2i extent{0, 0};  // texels
  bool dense = true;             // no empty column
  long sum_bottom = 0;           // Σ bottom over the columns
};

Profile chart_profile(const FlatChart& fc, int r, double density, int gutter, int cell) {
  const Vec2 span = (r % 2 ? Vec2(fc.max.y() - fc.min.y(), fc.max.x() - fc.min.x()) : Vec2(fc.max - fc.min)) * density;
  Profile out;
  out.extent = Eigen::Vector2i(static_cast<int>(std::ceil(span.x())) + 2 * gutter + 1,
                               static_cast<int>(std::ceil(span.y())) + 2 * gutter + 1);
  const int cols = (out.extent.x() + cell - 1) / cell;
  std::vector<double> lo(cols, std::numeric_limits<double>::max()), hi(cols, std::numeric_limits<double>::lowest());
  const double g = gutter + 0.5;  // where the footprint starts in its box (texel centres at +0.5)
  auto place = [&](const Vec2& p) { return Vec2(turn(fc, r, p) * density + Vec2::Constant(g)); };
  // Widens the columns' extents by `extent(s0, s1, y0, y1)` over the columns
  // that x range [xmin, xmax] reaches (gutter included).
  auto add = [&](double xmin, double xmax, auto&& extent) {
    const int c0 = std::max(0, static_cast<int>(std::floor((xmin - gutter) / cell)));
    const int c1 = std::min(cols - 1, static_cast<int>(std::floor((xmax + gutter) / cell)));
    for (int c = c0; c <= c1; ++c) {
      double y0 = std::numeric_limits<double>::infinity(), y1 = -y0;
      extent(static_cast<double>(c) * cell - gutter, static_cast<double>(c + 1) * cell + gutter, y0, y1);
      if (!(y0 <= y1)) continue;
      lo[c] = std::min(lo[c], y0);
      hi[c] = std::max(hi[c], y1);
    }
  };
  for (const int e : fc.outline.border_edges) {
    const auto& corners = fc.corners[e / 3];
    const Vec2 a = place(corners[e % 3]), b = place(corners[(e % 3 + 1) % 3]);
    add(std::min(a.x(), b.x()), std::max(a.x(), b.x()),
        [&](double s0, double s1, double& y0, double& y1) { segment_slab_extent(a, b, 0, s0, s1, y0, y1); });
  }
  for (const int f : fc.outline.loose_faces) {
    std::array<Vec2, 3> t;
    for (int k = 0; k < 3; ++k) t[k] = place(fc.corners[f][k]);
    add(std::min({t[0].x(), t[1].x(), t[2].x()}), std::max({t[0].x(), t[1].x(), t[2].x()}),
        [&](double s0, double s1, double& y0, double& y1) { slab_extent(t, 0, s0, s1, y0, y1); });
  }
  out.bottom.assign(cols, 1);
  out.top.assign(cols, 0);
  for (int c = 0; c < cols; ++c) {
    if (lo[c] > hi[c]) {
      out.dense = false;
      continue;
    }
    out.bottom[c] = std::max(0, static_cast<int>(std::floor((lo[c] - gutter) / cell)));
    out.sum_bottom += out.bottom[c];
    out.top[c] = static_cast<int>(std::ceil((hi[c] + gutter) / cell));
    out.top_max = std::max(out.top_max, out.top[c]);
  }
  out.extent.y() = std::max(out.extent.y(), out.top_max * cell);
  out.extent.x() = cols * cell;
  return out;
}

/// One tile's horizon: per column of cells, the top of what is placed.
class Horizon {
 public:
  explicit Horizon(int cells) : cols_(cells), rows_(cells), horizon_(cells, 0), below_(cells + 1, 0) {}

  /// Where a chart with these profiles (four rotations) comes to rest wasting
  /// the least area under it, raising the maximum counting as a full row
  /// wasted (ties: lower column, then lower rotation); false when it does
  /// not fit.
  bool best_fit(const std::array<Profile, 4>& profiles, int& best_x, int& best_y, int& best_r) const {
    long best_score = std::numeric_limits<long>::max();
    best_x = -1;
    for (int r = 0; r < 4; ++r) {
      const Profile& p = profiles[r];
      const int w = static_cast<int>(p.bottom.size());
      if (w > cols_ || p.top_max > rows_) continue;
      for (int x = 0; x + w <= cols_; ++x) {
        int y = 0;
        long waste = 0;
        if (!rest(p, x, y, waste)) continue;
        waste += static_cast<long>(std::max(0, y + p.top_max - max_)) * cols_;
        if (waste < best_score) best_score = waste, best_x = x, best_y = y, best_r = r;
      }
    }
    return best_x >= 0;
  }

  bool is_empty() const { return max_ == 0; }

  void place(const Profile& p, int x, int y) {
    for (std::size_t c = 0; c < p.bottom.size(); ++c) {
      if (p.bottom[c] <= p.top[c]) horizon_[x + c] = std::max(horizon_[x + c], y + p.top[c]);
    }
    for (int c = x; c < cols_; ++c) below_[c + 1] = below_[c] + horizon_[c];
    max_ = std::max(max_, y + p.top_max);
  }

 private:
  /// The height `y` at which profile `p` dropped at column `x` rests, and the
  /// area it leaves empty under it; false when it sticks out of the top.
  bool rest(const Profile& p, int x, int& y, long& waste) const {
    const int w = static_cast<int>(p.bottom.size());
    if (p.dense) {  // the common case, in closed form: the same sums
      const int* h = horizon_.data() + x;
      const int* b = p.bottom.data();
      for (int c = 0; c < w; ++c) y = std::max(y, h[c] - b[c]);
      if (y + p.top_max > rows_) return false;
      waste = static_cast<long>(w) * y + p.sum_bottom - (below_[x + w] - below_[x]);
      return true;
    }
    for (int c = 0; c < w; ++c) {
      if (p.bottom[c] <= p.top[c]) y = std::max(y, horizon_[x + c] - p.bottom[c]);
    }
    if (y + p.top_max > rows_) return false;
    for (int c = 0; c < w; ++c) {
      if (p.bottom[c] <= p.top[c]) waste += y + p.bottom[c] - horizon_[x + c];
    }
    return true;
  }

  int cols_, rows_;
  std::vector<int> horizon_;
  std::vector<long> below_;  // below_[x]: Σ horizon_[0, x)
  int max_ = 0;
};

/// Packs chart shapes, not their boxes (the "Tetris" packing of Lévy et
/// al. 2002, Sec. 5) into at most `max_tiles` tiles of `size` texels: each
/// chart, largest first, is dropped in the first tile where it fits, at the
/// column and rotation (of four) where it comes to rest wasting the least
/// area under it (Horizon). Concave footprints nest into each other. A new
/// tile opens when no open one holds the chart. Deterministic. False when
/// the charts do not fit.
bool pack_shapes(const std::vector<FlatChart>& flat, double density, int size, int gutter, int max_tiles,
                 std::vector<Placement>& out) {
  const int cell = std::max(1, size / 512);
  const std::size_t m = flat.size();
  std::vector<std::array<Profile, 4>> profiles(m);
  std::vector<double> area(m, 0.0);
  tbb::parallel_for(std::size_t(0), m, [&](std::size_t c) {
    for (int r = 0; r < 4; ++r) profiles[c][r] = chart_profile(flat[c], r, density, gutter, cell);
    for (std::size_t k = 0; k < profiles[c][0].bottom.size(); ++k) {
      area[c] += std::max(0, profiles[c][0].top[k] - profiles[c][0].bottom[k]);
    }
  });
  std::vector<int> order(m);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return area[a] > area[b]; });
  std::vector<Horizon> tiles(1, Horizon(size / cell));
  out.assign(m, Placement{});
  for (int i : order) {
    int x = 0, y = 0, r = 0;
    std::size_t t = 0;
    while (!tiles[t].best_fit(profiles[i], x, y, r)) {
      if (++t < tiles.size()) continue;
      // A chart that an empty tile does not hold fits nowhere.
      if (static_cast<int>(tiles.size()) == max_tiles || tiles.back().is_empty()) return false;
      tiles.emplace_back(size / cell);
    }
    tiles[t].place(profiles[i][r], x, y);
    out[i].tile = static_cast<int>(t);
    out[i].rotation = r;
    out[i].origin = Eigen::Vector2i(x * cell, y * cell);
    out[i].extent = profiles[i][r].extent;
  }
  return true;
}

}  // namespace

namespace {

/// Charts that flattened well: faces, flat corners and area stretch each.
struct FlatCharts {
  std::vector<std::vector<int>> faces;
  std::vector<FlatChart> flat;
  std::vector<double> stretch;
  int failed = 0;  ///< charts cut in two (LSCM failed, too much stretch, too little of the box filled)
};

/// Disk-like charts of at most max_chart_faces, grown from every face not in
/// a chart yet (lowest first) over faces within the normal cone of the
/// seed, nearest first.
std::vector<std::vector<int>> grow_charts(const SurfaceIndex& surface, const AtlasOptions& options) {
  const FrameMesh& mesh = surface.mesh();
  auto centroid = [&](int f) {
    const Tri& t = mesh.triangles[f];
    return Vec3((mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0);
  };
  std::vector<char> assigned(mesh.triangles.size(), 0);
  std::vector<std::vector<int>> charts;
  for (int seed = 0; seed < static_cast<int>(mesh.triangles.size()); ++seed) {
    if (assigned[seed]) continue;
    const Vec3 n0 = surface.face_normals()[seed];
    const Vec3 c0 = centroid(seed);
    DiskRegionOptions region;
    region.accept = [&](int f) { return !assigned[f] && surface.face_normals()[f].dot(n0) > options.normal_cone; };
    region.priority = [&](int f) { return (centroid(f) - c0).squaredNorm(); };
    region.max_faces = options.max_chart_faces;
    std::vector<int> faces = grow_disk_region(surface, seed, region);
    for (int f : faces) assigned[f] = 1;
    charts.push_back(std::move(faces));
  }
  return charts;
}

/// A chart that failed, cut into disks of at most half its faces: each
/// grown from the first face left in order of `key` (lowest first) over the
/// chart's faces left, lowest key first, until every face has a piece.
/// `owner`: per surface face, scratch (the chart's faces are marked `tag`).
std::vector<std::vector<int>> split_chart(const SurfaceIndex& surface, const std::vector<int>& faces,
                                          const std::vector<double>& key, std::vector<int>& owner, int tag) {
  for (int f : faces) owner[f] = tag;
  std::vector<int> order = faces;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return std::tie(key[a], a) < std::tie(key[b], b); });
  DiskRegionOptions region;
  region.accept = [&](int f) { return owner[f] == tag; };
  region.priority = [&](int f) { return key[f]; };
  region.max_faces = std::max<std::size_t>(1, faces.size() / 2);
  std::vector<std::vector<int>> pieces;
  for (int seed : order) {
    if (owner[seed] != tag) continue;
    std::vector<int> piece = grow_disk_region(surface, seed, region);
    for (int f : piece) owner[f] = -1;
    pieces.push_back(std::move(piece));
  }
  return pieces;
}

/// Steps 1–2: segment into disk-like charts bounded by a normal cone,
/// flatten each (in parallel, each into its own slot), and cut in two
/// (split_chart) every chart LSCM could not flatten, flattened with too much
/// area distortion, that fills less than min_fill of its box, or that is
/// longer than one tile at a given texel density; its pieces
/// are flattened and tested in the next round. A flattened chart is cut
/// across its long side (the pieces are swept from one end, a sweep the
/// disk growth keeps whole), one LSCM could not flatten by distance from its
/// seed. Each piece has at most half its chart's faces, and a single face is
/// always flat, so the rounds end.
FlatCharts segment_and_flatten(const SurfaceIndex& surface, const AtlasOptions& options) {
  const FrameMesh& mesh = surface.mesh();
  // At a given density, a chart must fit in one tile with its gutter (and
  // the packer's cell of rounding): a longer one is cut too.
  const double max_span =
      options.texel_density
          ? (options.size - 2 * options.gutter - 2 - std::max(1, options.size / 512)) / *options.texel_density
          : std::numeric_limits<double>::infinity();
  const std::size_t nf = mesh.triangles.size();
  FlatCharts out;
  std::vector<std::vector<int>> chart_faces = grow_charts(surface, options);
  std::vector<double> key(nf, 0.0);
  std::vector<int> owner(nf, -1);
  int tag = 0;
  while (!chart_faces.empty()) {
    std::vector<FlatChart> flat(chart_faces.size());
    std::vector<double> stretch(chart_faces.size(), 1.0);
    std::vector<char> flattened(chart_faces.size(), 1), ok(chart_faces.size(), 1);
    tbb::parallel_for(std::size_t(0), chart_faces.size(), [&](std::size_t c) {
      if (chart_faces[c].size() == 1) {
        flat[c] = flat_face(mesh, chart_faces[c][0]);
        return;
      }
      flattened[c] = flatten_chart(mesh, chart_faces[c], flat[c], stretch[c]);
      ok[c] = flattened[c] && stretch[c] <= options.max_stretch &&
              (chart_faces[c].size() <= options.min_fill_faces || box_fill(flat[c]) >= options.min_fill) &&
              (flat[c].max - flat[c].min).maxCoeff() <= max_span;
    });
    std::vector<std::vector<int>> next;
    for (std::size_t c = 0; c < chart_faces.size(); ++c) {
      const std::vector<int>& faces = chart_faces[c];
      if (ok[c]) {
        out.faces.push_back(std::move(chart_faces[c]));
        out.flat.push_back(std::move(flat[c]));
        out.stretch.push_back(stretch[c]);
        continue;
      }
      ++out.failed;
      if (flattened[c]) {
        const FlatChart& fc = flat[c];
        const int axis = fc.max.x() - fc.min.x() >= fc.max.y() - fc.min.y() ? 0 : 1;
        for (std::size_t i = 0; i < faces.size(); ++i) {
          key[faces[i]] = fc.corners[i][0][axis] + fc.corners[i][1][axis] + fc.corners[i][2][axis];
        }
      } else {
        const Vec3 seed = mesh.positions[mesh.triangles[faces[0]][0]];
        for (int f : faces) key[f] = (mesh.positions[mesh.triangles[f][0]] - seed).squaredNorm();
      }
      for (std::vector<int>& piece : split_chart(surface, faces, key, owner, tag++)) next.push_back(std::move(piece));
    }
    chart_faces = std::move(next);
  }
  return out;
}

/// Step 3: the largest common density (texels per scene unit, by bisection)
/// at which the charts pack into the atlas, and their placements there.
double pack_density(const SurfaceIndex& surface, const std::vector<FlatChart>& flat, const AtlasOptions& options,
                    std::vector<Placement>& placement) {
  const double area3 = surface.area();
  const int n = options.size;
  double lo = 0.0, hi = area3 > 0.0 ? std::sqrt(static_cast<double>(n) * n / area3) : 1.0;  // 100% would be this
  // Density to 1/1024 of the 100% bound: at the usual 50–60% packing, within
  // 0.3% of the densest that fits in texel count (15 packings to 1/16384
  // cost half as much again, for nothing seen). The densest packing that
  // fitted is kept, not packed again.
  std::vector<Placement> trial;
  for (int iter = 0; iter < 10; ++iter) {
    const double mid = 0.5 * (lo + hi);
    if (pack_shapes(flat, mid, n, options.gutter, 1, trial)) {
      lo = mid;
      placement.swap(trial);
    } else {
      hi = mid;
    }
  }
  if (!(lo > 0.0)) {
    throw InputError("", "atlas: " + std::to_string(flat.size()) + " charts do not fit in " + std::to_string(n) + "x" +
                             std::to_string(n) + " texels with --gutter " + std::to_string(options.gutter) +
                             "; raise --atlas-size");
  }
  return lo;
}

/// Step 3, at a given density: the smallest square, a multiple of 64 texels
/// up to options.size, into which the charts pack at `density` (by
/// bisection over the multiples), and their placements there; when one
/// options.size square is not enough, as many such tiles as the charts need
/// (up to options.max_tiles).
int pack_size(const SurfaceIndex& surface, const std::vector<FlatChart>& flat, const AtlasOptions& options,
              double density, std::vector<Placement>& placement) {
  constexpr int kStep = 64;
  // No square smaller than the charts' area at 100 % packing holds them.
  const double least = std::sqrt(surface.area()) * density;
  int lo = std::max(1, static_cast<int>(std::ceil(least / kStep)));  // in steps; lo − 1 steps never fit
  int hi = options.size / kStep;
  std::vector<Placement> trial;
  int fits = 0;
  if (hi >= lo && pack_shapes(flat, density, hi * kStep, options.gutter, 1, trial)) {
    fits = hi;
    placement.swap(trial);
    while (lo < fits) {
      const int mid = (lo + fits) / 2;
      if (pack_shapes(flat, density, mid * kStep, options.gutter, 1, trial)) {
        fits = mid;
        placement.swap(trial);
      } else {
        lo = mid + 1;
      }
    }
    return fits * kStep;
  }
  const std::string square = std::to_string(options.size) + "x" + std::to_string(options.size) + " texels";
  const std::string needs = "atlas: at --texel-density " + format_number(density) + " the surface (area " +
                            format_number(surface.area()) + ")";
  if (options.max_tiles == 1) {
    throw InputError("", needs + " needs more than " + square +
                             ": lower --texel-density, raise --atlas-size (at most 32768) or put <UDIM> in --atlas "
                             "for UDIM tiles");
  }
  if (!pack_shapes(flat, density, options.size, options.gutter, options.max_tiles, placement)) {
    throw InputError("", needs + " needs more than " + std::to_string(options.max_tiles) + " UDIM tiles of " + square +
                             ", or has a chart larger than one: lower --texel-density or raise --atlas-size");
  }
  return options.size;
}

}  // namespace

Atlas build_atlas(const SurfaceIndex& surface, const AtlasOptions& options) {
  options.validate();
  const std::size_t nf = surface.mesh().triangles.size();
  Atlas atlas;
  atlas.size = options.size;
  atlas.face_chart.assign(nf, -1);
  atlas.corner_px.assign(nf, {});
  FlatCharts charts = segment_and_flatten(surface, options);
  atlas.failed_charts = charts.failed;
  std::vector<Placement> placement;
  const double density =
      options.texel_density ? *options.texel_density : pack_density(surface, charts.flat, options, placement);
  if (options.texel_density) atlas.size = pack_size(surface, charts.flat, options, density, placement);
  atlas.texels_per_unit = density;
  for (const Placement& p : placement) atlas.tiles = std::max(atlas.tiles, p.tile + 1);

  // 4. Corner positions in texels.
  atlas.charts.resize(charts.faces.size());
  double chart_area_px = 0.0;
  for (std::size_t c = 0; c < charts.faces.size(); ++c) {
    Chart& chart = atlas.charts[c];
    chart.faces = std::move(charts.faces[c]);
    chart.tile = placement[c].tile;
    chart.origin = placement[c].origin;
    chart.extent = placement[c].extent;
    chart.stretch = charts.stretch[c];
    const FlatChart& fc = charts.flat[c];
    const Vec2 offset = placement[c].origin.cast<double>() + Vec2::Constant(options.gutter + 0.5);
    auto place = [&](const Vec2& p) { return Vec2(turn(fc, placement[c].rotation, p) * density + offset); };
    for (std::size_t i = 0; i < chart.faces.size(); ++i) {
      const int f = chart.faces[i];
      atlas.face_chart[f] = static_cast<int>(c);
      for (int k = 0; k < 3; ++k) atlas.corner_px[f][k] = place(fc.corners[i][k]);
      chart.area3 += surface.face_areas()[f];
    }
    chart_area_px += chart.area3 * density * density;
  }
  atlas.packing_efficiency = chart_area_px / (static_cast<double>(atlas.size) * atlas.size * atlas.tiles);
  return atlas;
}

UVMesh atlas_uv_mesh(const SurfaceIndex& surface, const Atlas& atlas) {
  const FrameMesh& mesh = surface.mesh();
  UVMesh out;
  out.positions = mesh.positions;
  out.normals = surface.vertex_normals();
  out.velocities = mesh.velocities;
  out.triangles = mesh.triangles;
  out.uv_triangles.resize(mesh.triangles.size());
  std::unordered_map<std::uint64_t, int> shared;  // (vertex, chart) -> uv index
  const double inv = 1.0 / atlas.size;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const Vec2 tile = udim_offset(atlas.charts[atlas.face_chart[f]].tile);
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t key =
          (static_cast<std::uint64_t>(mesh.triangles[f][k]) << 32) | static_cast<std::uint32_t>(atlas.face_chart[f]);
      auto [it, inserted] = shared.emplace(key, static_cast<int>(out.uvs.size()));
      if (inserted) {
        const Vec2& p = atlas.corner_px[f][k];
        out.uvs.emplace_back(tile.x() + p.x() * inv, tile.y() + (1.0 - p.y() * inv));
      }
      out.uv_triangles[f][k] = it->second;
    }
  }
  return out;
}

}  // namespace fluidtex
