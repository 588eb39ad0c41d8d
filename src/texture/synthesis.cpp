#include "fluidtex/texture/synthesis.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <tuple>

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>

#include "fluidtex/tracking/advection.h"
#include "fluidtex/tracking/patch_coverage.h"
#include "fluidtex/tracking/patch_locator.h"
#include "fluidtex/util/check.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/random.h"

namespace fluidtex {

namespace {

constexpr int kTile = 64;
constexpr std::size_t kTileTexels = static_cast<std::size_t>(kTile) * kTile;
/// Texels whose centres lie this far (in texels) outside a rasterised
/// triangle are still tested: far more than the barycentric tolerance of
/// the test itself at any triangle size an atlas holds.
constexpr double kSpanMargin = 0.01;

/// 2D barycentric coordinates of p in (a, b, c); false when degenerate.
bool bary2(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c, Vec3& out) {
  const double det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
  if (!(std::abs(det) > 1e-300)) return false;
  const double l1 = ((p.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (p.y() - a.y())) / det;
  const double l2 = ((b.x() - a.x()) * (p.y() - a.y()) - (p.x() - a.x()) * (b.y() - a.y())) / det;
  out = Vec3(1.0 - l1 - l2, l1, l2);
  return true;
}

/// Texel (x, y)'s centre in atlas coordinates.
Vec2 texel_centre(int x, int y) { return Vec2(x + 0.5, y + 0.5); }

/// A per-vertex quantity of a surface face as an affine function of atlas
/// coordinates: v(x, y) = origin + x·dx + y·dy, the barycentric blend at the
/// atlas point (x, y) of the face's corners `p` (the texel map's barycentrics
/// are affine in the texel centre, up to their clamp into the face, which
/// moves a texel by at most 1e-9 of the face). False for a degenerate face,
/// which holds no texels.
bool atlas_affine(const std::array<Vec2, 3>& p, const Vec3& a, const Vec3& b, const Vec3& c,
                  TriangleProjection::Affine3& out) {
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec2 u = p[1] - p[0], v = p[2] - p[0];
  const double det = u.x() * v.y() - v.x() * u.y();
  if (!(std::abs(det) > 1e-300)) return false;
  // (l1, l2) = M⁻¹((x, y) − p0), M = [u v]; value = a + l1·e1 + l2·e2.
  out.dx = (v.y() * e1 - u.y() * e2) / det;
  out.dy = (u.x() * e2 - v.x() * e1) / det;
  out.origin = a - p[0].x() * out.dx - p[0].y() * out.dy;
  return out.origin.allFinite() && out.dx.allFinite() && out.dy.allFinite();
}

/// The rows of a face's texels that a set of half-spaces n·q ≥ c − margin
/// (TrianglePrism::half_spaces) leaves, each half-space as a bound on the
/// texel centre's x: a·x + b·y + o ≥ 0 on the face's points (atlas_affine);
/// and the face's own triangle in the atlas (its texels' barycentrics are
/// at least −1e-9, build_texel_map), so that a span holds few texels of
/// other faces.
class RowSpans {
 public:
  RowSpans(const TriangleProjection::Affine3& plane, const std::array<TrianglePrism::HalfSpace, 5>& hs, double margin,
           const std::array<Vec2, 3>& face_px) {
    for (const TrianglePrism::HalfSpace& h : hs)
      add(h.n.dot(plane.dx), h.n.dot(plane.dy), h.n.dot(plane.origin) - h.c + margin);
    // l_k(x, y) ≥ −1e-9 (a little looser, for rounding) for the face's
    // barycentrics, affine in the atlas position (bary2).
    const Vec2 &p0 = face_px[0], &p1 = face_px[1], &p2 = face_px[2];
    const double det = (p1.x() - p0.x()) * (p2.y() - p0.y()) - (p2.x() - p0.x()) * (p1.y() - p0.y());
    if (!(std::abs(det) > 1e-300)) return;
    const double slack = 1e-9 + 1e-7;
    for (int k = 0; k < 3; ++k) {
      // l_k is 1 at corner k and 0 on the opposite edge (from corner k + 1 to k + 2).
      const Vec2& e0 = face_px[(k + 1) % 3];
      const Vec2& e1 = face_px[(k + 2) % 3];
      const double a = (e0.y() - e1.y()) / det, b = (e1.x() - e0.x()) / det;
      add(a, b, -(a * e0.x() + b * e0.y()) + slack);
    }
  }

  /// Narrows [x0, x1) to the texels of row y whose centres may pass; false
  /// when none can.
  bool row(int y, int& x0, int& x1) const {
    double lo = -std::numeric_limits<double>::infinity(), hi = -lo;
    const double yc = y + 0.5;
    for (int k = 0; k < count_; ++k) {
      const double rest = o_[k] + yc * b_[k];  // a·xc + rest ≥ 0
      if (a_[k] > 0.0)
        lo = std::max(lo, -rest * inv_a_[k]);
      else if (a_[k] < 0.0)
        hi = std::min(hi, -rest * inv_a_[k]);
      else if (rest < 0.0)
        return false;
    }
    if (!(lo <= hi)) return false;
    // Centres x + ½ in [lo, hi], within [x0, x1) (clamped in double: lo and
    // hi may be far outside int).
    const double first = std::clamp(std::ceil(lo - 0.5), double(x0), double(x1));
    const double end = std::clamp(std::floor(hi - 0.5) + 1.0, double(x0), double(x1));
    x0 = static_cast<int>(first), x1 = static_cast<int>(end);
    return x0 < x1;
  }

 private:
  /// a·x + b·y + o ≥ 0; an `a` too small to invert bounds nothing in x.
  void add(double a, double b, double o) {
    const double inv = 1.0 / a;
    a_[count_] = std::isfinite(inv) ? a : 0.0, b_[count_] = b, o_[count_] = o, inv_a_[count_] = inv;
    ++count_;
  }
  std::array<double, 8> a_, b_, o_, inv_a_;
  int count_ = 0;
};

/// One patch's contribution to a texel, kept until the texel's largest core
/// weight is known (SynthesisOptions::weight_cutoff).
struct Contribution {
  std::uint32_t texel;  // tile-local
  int patch;
  Vec2 uv;
  double core, tail;  // core weight (K_S·K_t) and coverage tail
};

/// A tile's contributions, in the order they came (per texel: patch order),
/// with each texel's Σcore and largest core.
struct Accumulator {
  std::vector<Contribution> list;
  std::vector<double> sum_core, max_core;
  std::vector<int> last_patch;          // per texel: the patch of its last entry
  std::vector<std::size_t> last_entry;  // per texel: that entry's index in `list`
  explicit Accumulator(std::size_t n) : sum_core(n, 0.0), max_core(n, 0.0), last_patch(n, -1), last_entry(n, 0) {}
  /// Back to empty: only the texels with an entry were written.
  /// `also(texel)` is called once for each of those texels (at its last entry).
  template <class F>
  void clear(F&& also) {
    for (std::size_t e = 0; e < list.size(); ++e) {
      const std::uint32_t i = list[e].texel;
      if (last_entry[i] != e) continue;
      sum_core[i] = 0.0, max_core[i] = 0.0, last_patch[i] = -1;
      also(i);
    }
    list.clear();
  }
};

/// A texel's sums of the blended samples, in double so that the fixed
/// summation order is the only thing that decides the result. A
/// contribution's weight is its (cut) core plus λ times its coverage tail,
/// λ = 1 − Σcore/ε clamped to [0, 1] (see SynthesisOptions::radius): core and
/// tail sums are kept apart and combined once λ is applied. One texel's sums
/// lie together (two cache lines).
struct TexelSum {
  std::array<double, 3> sum{}, tail_sum{};  // per channel: Σ core·c, Σ tail·c
  double sum_w = 0.0, sum_w2 = 0.0;         // Σcore, Σcore²
  double tail_w = 0.0, tail_w2 = 0.0;       // Σtail, Σtail²
  double cross = 0.0, best_w = 0.0;         // Σcore·tail, the largest blended weight
  int count = 0, tail_count = 0, best_patch = -1;
};

/// Adds patch contributions to a tile's texels (once per patch and texel)
/// and blends them.
struct Contributor {
  const std::vector<Patch>& patches;
  const std::vector<std::vector<float>>& core;  // per patch and vertex: core_weight
  const Blender& blender;
  const SynthesisOptions& options;
  double lookup_scale;  // s / tile_size

  /// Full weight w (patch.weight interpolated) and core weight at the
  /// barycentrics `l` of triangle `tri` of `patch`.
  std::pair<double, double> weights(int patch, const Tri& tri, const Vec3& l) const {
    const Patch& p = patches[patch];
    const std::vector<float>& c = core[patch];
    return {interpolate(p.weight, tri, l), interpolate(c, tri, l)};
  }

  void sample(int patch, const Vec2& uv, double* term) const {
    const Patch& p = patches[patch];
    const Vec2 at = p.anchor + lookup_scale * (uv + p.texture_offset);
    blender.sample(at.x(), at.y(), term);
  }

  /// A patch contributes once per texel, through the first of its
  /// triangles over the texel, except that a triangle that brings a core
  /// weight replaces one that brought only its coverage tail (a border
  /// triangle, whose vertices carry the tail alone).
  void add(Accumulator& acc, std::size_t i, int patch, const Vec2& uv, double w, double core) const {
    if (!(w > 0.0)) return;
    const double tail = std::max(0.0, w - core);
    if (acc.last_patch[i] == patch) {
      Contribution& k = acc.list[acc.last_entry[i]];
      if (k.core > 0.0 || !(core > 0.0)) return;
      acc.sum_core[i] += core;
      k.uv = uv, k.core = core, k.tail = tail;
    } else {
      acc.last_patch[i] = patch;
      acc.last_entry[i] = acc.list.size();
      acc.list.push_back({static_cast<std::uint32_t>(i), patch, uv, core, tail});
      acc.sum_core[i] += core;
    }
    acc.max_core[i] = std::max(acc.max_core[i], core);
  }

  /// λ of a texel with Σcore `sum_core` (1: bare of cores, the tails fill
  /// it; 0: the cores alone).
  double tail_share(double sum_core) const {
    const double epsilon = kCoverageTail * options.uv_scale;
    return std::clamp(1.0 - sum_core / epsilon, 0.0, 1.0);
  }

  /// The core weight a texel blends: lowered by the cutoff times the texel's
  /// largest core, so that a patch enters and leaves a texel continuously,
  /// then sharpened (SynthesisOptions::sharpness).
  double cut(double core, double max_core) const {
    const double top = (1.0 - options.weight_cutoff) * max_core;
    return sharpened(std::max(0.0, core - options.weight_cutoff * max_core), top, options.sharpness);
  }

  /// Blends the tile's contributions into `s`: every contribution with a
  /// core (its tail too, for λ), then the tail-only contributions of texels
  /// with λ > 0, each in the order they came. A sample is looked up only for
  /// a weight that counts.
  void blend(const Accumulator& acc, std::vector<TexelSum>& sums) const {
    const int nc = blender.channels();
    double term[3] = {0, 0, 0};
    for (const Contribution& k : acc.list) {
      if (!(k.core > 0.0)) continue;
      const std::size_t i = k.texel;
      const double core = cut(k.core, acc.max_core[i]);
      if (!(core > 0.0) && !(k.tail > 0.0 && tail_share(acc.sum_core[i]) > 0.0)) continue;
      sample(k.patch, k.uv, term);
      TexelSum& s = sums[i];
      for (int c = 0; c < nc; ++c) {
        s.sum[c] += core * term[c];
        s.tail_sum[c] += k.tail * term[c];
      }
      s.sum_w += core;
      s.sum_w2 += core * core;
      s.tail_w += k.tail;
      s.tail_w2 += k.tail * k.tail;
      s.cross += core * k.tail;
      if (core > 0.0) ++s.count;
      if (core > s.best_w) s.best_w = core, s.best_patch = k.patch;
    }
    for (const Contribution& k : acc.list) {
      if (k.core > 0.0) continue;
      const std::size_t i = k.texel;
      const double lambda = tail_share(acc.sum_core[i]);
      if (!(lambda > 0.0)) continue;
      sample(k.patch, k.uv, term);
      TexelSum& s = sums[i];
      for (int c = 0; c < nc; ++c) s.tail_sum[c] += k.tail * term[c];
      s.tail_w += k.tail;
      s.tail_w2 += k.tail * k.tail;
      ++s.tail_count;
      if (lambda * k.tail > s.best_w) s.best_w = lambda * k.tail, s.best_patch = k.patch;
    }
  }
};

}  // namespace

Vec3 TexelMap::bary(std::size_t i) const {
  FLUIDTEX_DCHECK(face[i] >= 0);
  const auto& p = corner_px[static_cast<std::size_t>(face[i])];
  // build_texel_map claimed the texel with these same corners, so bary2
  // succeeds; the initial value only keeps the compiler's flow analysis quiet.
  Vec3 l = Vec3::Constant(1.0 / 3.0);
  [[maybe_unused]] const bool ok =
      bary2(texel_centre(static_cast<int>(i % size), static_cast<int>(i / size)), p[0], p[1], p[2], l);
  FLUIDTEX_DCHECK(ok);
  l = l.cwiseMax(0.0);
  return l / l.sum();
}

TexelMap build_texel_map(const SurfaceIndex& surface, const Atlas& atlas, int tile) {
  const int n = atlas.size;
  const std::size_t nf = surface.mesh().triangles.size();
  TexelMap map;
  map.size = n;
  map.tile = tile;
  map.face.assign(static_cast<std::size_t>(n) * n, -1);
  map.corner_px = atlas.corner_px;
  // Charts own disjoint rectangles: rasterise them in parallel, faces of a
  // chart in order (the first face to claim a texel keeps it).
  tbb::parallel_for(std::size_t(0), atlas.charts.size(), [&](std::size_t c) {
    if (atlas.charts[c].tile != tile) return;
    for (int f : atlas.charts[c].faces) {
      const auto& p = atlas.corner_px[f];
      const Vec2 lo = p[0].cwiseMin(p[1]).cwiseMin(p[2]), hi = p[0].cwiseMax(p[1]).cwiseMax(p[2]);
      (texel_box(lo, hi) & Rect2i{0, 0, n, n}).for_each([&](int x, int y) {
        Vec3 l;
        if (!bary2(texel_centre(x, y), p[0], p[1], p[2], l)) return;
        if (l.minCoeff() < -1e-9) return;
        const std::size_t i = texel_index(x, y, n);
        if (map.face[i] < 0) map.face[i] = f;
      });
    }
  });
  // Group texels by face (counting sort, ascending texel index per face).
  map.face_start.assign(nf + 1, 0);
  for (int f : map.face) {
    if (f >= 0) ++map.face_start[f + 1];
  }
  for (std::size_t f = 0; f < nf; ++f) map.face_start[f + 1] += map.face_start[f];
  map.texels.resize(map.face_start[nf]);
  std::vector<std::uint32_t> fill(map.face_start.begin(), map.face_start.end() - 1);
  for (std::size_t i = 0; i < map.face.size(); ++i) {
    if (map.face[i] >= 0) map.texels[fill[map.face[i]]++] = static_cast<std::uint32_t>(i);
  }
  return map;
}

namespace {

/// Calls f(texel index) for each 8-neighbour of (x, y) inside a w × h image.
template <class F>
void for_neighbours(int x, int y, int w, int h, F&& f) {
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const int xx = x + dx, yy = y + dy;
      if (xx < 0 || yy < 0 || xx >= w || yy >= h || (dx == 0 && dy == 0)) continue;
      f(texel_index(xx, yy, w));
    }
  }
}

/// The empty texels of `mask` (w × h) with a filled 8-neighbour, in texel
/// order: per row, the filled texels of the rows above, at and below it,
/// ORed over each texel's column and its two neighbours (branch-free loops).
std::vector<std::uint32_t> dilation_front(const std::vector<char>& mask, int w, int h) {
  std::vector<std::vector<std::uint32_t>> rows(static_cast<std::size_t>(h));
  tbb::parallel_for(0, h, [&](int y) {
    std::vector<char> column(static_cast<std::size_t>(w), 0);
    for (int yy = std::max(0, y - 1); yy <= std::min(h - 1, y + 1); ++yy) {
      const char* m = mask.data() + texel_index(0, yy, w);
      for (int x = 0; x < w; ++x) column[x] |= m[x];
    }
    const char* here = mask.data() + texel_index(0, y, w);
    for (int x = 0; x < w; ++x) {
      const bool near = column[x] | (x > 0 && column[x - 1]) | (x + 1 < w && column[x + 1]);
      if (near && !here[x]) rows[y].push_back(static_cast<std::uint32_t>(texel_index(x, y, w)));
    }
  });
  std::vector<std::uint32_t> front;
  for (const auto& row : rows) front.insert(front.end(), row.begin(), row.end());
  return front;
}

}  // namespace

void dilate(Image& image, std::vector<char>& mask, int rings) {
  const int w = image.width, h = image.height, nc = image.channels;
  if (w <= 0 || h <= 0 || rings <= 0) return;
  // Each ring fills the front: the empty texels with a filled 8-neighbour
  // as the ring starts. The first front is found by one pass over the image;
  // every later one lies among the 8-neighbours of the last.
  std::vector<std::uint32_t> front = dilation_front(mask, w, h);
  std::vector<char> queued(static_cast<std::size_t>(w) * h, 0);
  for (std::uint32_t i : front) queued[i] = 1;
  std::vector<std::uint32_t> next;
  for (int ring = 0; ring < rings && !front.empty(); ++ring) {
    // The front's texels read only texels filled before the ring.
    tbb::parallel_for(std::size_t(0), front.size(), [&](std::size_t k) {
      const std::size_t i = front[k];
      const int x = static_cast<int>(i % w), y = static_cast<int>(i / w);
      float acc[4] = {0, 0, 0, 0};
      int n = 0;
      for_neighbours(x, y, w, h, [&](std::size_t j) {
        if (!mask[j]) return;
        for (int c = 0; c < nc; ++c) acc[c] += image.pixel(j)[c];
        ++n;
      });
      for (int c = 0; c < nc; ++c) image.pixel(i)[c] = acc[c] / static_cast<float>(n);
    });
    for (std::uint32_t i : front) mask[i] = 1;
    next.clear();
    for (std::uint32_t i : front) {
      for_neighbours(static_cast<int>(i % w), static_cast<int>(i / w), w, h, [&](std::size_t j) {
        if (mask[j] || queued[j]) return;
        queued[j] = 1;
        next.push_back(static_cast<std::uint32_t>(j));
      });
    }
    front.swap(next);
  }
}

namespace {

/// A patch triangle in a tile's list: rasterised in one chart
/// (`regions` < 0) or projected per texel over the regions of
/// `region_lists[regions]` (the projected fallback).
struct Job {
  int patch, tri;
  int regions;
};

/// Per surface face under a patch triangle of the projected fallback: the
/// atlas texels outside which none of the face's texels can project into the
/// patch triangle.
struct Region {
  int face;
  Rect2i rect;
};

/// Every patch triangle binned into the atlas tiles it may touch, each
/// tile's list in patch order.
struct TriangleBins {
  std::vector<std::vector<Job>> jobs;  // per tile
  std::vector<std::vector<Region>> region_lists;
  std::vector<std::array<Vec2, 3>> tri_px;  // atlas corners of raster jobs, by (patch, tri) order
  std::vector<std::uint8_t> tri_rim;        // bit k: edge k (corners k, k+1) is on the patch's boundary
  std::vector<std::size_t> tri_px_base;     // first (patch, tri) slot of each patch
  std::size_t binned = 0;                   // triangles with a core weight
  std::size_t projected = 0;                // of those, sent to the projected fallback
};

/// The projected fallback's hits of the current patch, per tile-local texel
/// (its nearest triangle wins).
struct ProjectedHits {
  struct Hit {
    double dist2 = std::numeric_limits<double>::infinity();
    Vec2 uv = Vec2::Zero();
    double w = 0.0, core = 0.0;
  };
  int patch = -1;
  std::vector<Hit> hit = std::vector<Hit>(kTileTexels);
  std::vector<std::size_t> texels;  // with a hit, in first-hit order

  /// Adds the current patch's hits to `acc` and clears them.
  void flush(const Contributor& contribute, Accumulator& acc) {
    for (std::size_t j : texels) {
      contribute.add(acc, j, patch, hit[j].uv, hit[j].w, hit[j].core);
      hit[j] = Hit{};
    }
    texels.clear();
  }
};

/// One atlas tile's texels and their sums: a thread's workspace, taken up by
/// one tile after another (start()), so that no tile allocates.
struct TileSums {
  Rect2i rect;
  Accumulator acc{kTileTexels};
  std::vector<TexelSum> sums{kTileTexels};
  ProjectedHits projected;
  TileSums() = default;
  /// Empties the workspace (what the last tile wrote) for tile `r`.
  void start(const Rect2i& r) {
    acc.clear([&](std::uint32_t i) { sums[i] = TexelSum{}; });
    projected.patch = -1;
    rect = r;
  }
  /// Tile-local index of atlas texel (x, y).
  std::size_t local(int x, int y) const {
    FLUIDTEX_DCHECK(x >= rect.x0 && x < rect.x1 && y >= rect.y0 && y < rect.y1);
    return texel_index(x - rect.x0, y - rect.y0, kTile);
  }
};

/// Per-tile counts of chart, bare, margin-filled (accumulate_tails),
/// clamped and dominated (kDominantWeight) texels.
struct Tally {
  std::size_t chart = 0, bare = 0, margin = 0, clamped = 0, dominant = 0;
};

/// One frame's synthesis: binning, then per tile raster, projected fallback
/// and resolve.
/// One patch's binned triangles, before they join the frame's bins.
struct PatchBins {
  std::vector<std::pair<int, Job>> placed;  // (tile, job); job.regions indexes `lists`
  std::vector<std::vector<Region>> lists;
  std::size_t binned = 0, projected = 0;
};

/// The patches' bins into `bins`, in patch order (region lists renumbered).
void merge_patch_bins(std::vector<PatchBins>& per_patch, TriangleBins& bins) {
  for (PatchBins& b : per_patch) {
    const int offset = static_cast<int>(bins.region_lists.size());
    for (auto& list : b.lists) bins.region_lists.push_back(std::move(list));
    for (auto [tile, job] : b.placed) {
      if (job.regions >= 0) job.regions += offset;
      bins.jobs[tile].push_back(job);
    }
    bins.binned += b.binned;
    bins.projected += b.projected;
  }
}

/// How a patch triangle reaches the texels of the tile being synthesised.
enum class Route : std::uint8_t {
  Raster,     ///< in atlas space, within one chart of the tile
  Projected,  ///< through the surface faces under it (projected_regions)
  Elsewhere,  ///< not at all: it lies within a chart of another tile
};

class Synthesizer {
 public:
  Synthesizer(const SurfaceIndex& surface, const Atlas& atlas, const TexelMap& map, const std::vector<Patch>& patches,
              const Exemplar& exemplar, const SynthesisOptions& options)
      : surface_(surface), atlas_(atlas), map_(map), patches_(patches), exemplar_(exemplar), options_(options),
        n_(atlas.size), tiles_{n_, n_, kTile}, tolerance_(options.projection_tolerance),
        blender_(exemplar, options.blend),
        // Texels just outside a patch's boundary edge still take it (the same
        // in-plane slack as the projection): the corners of a polygonal rim
        // between two patch border points would be holes otherwise.
        slack_px_(projection_slack(tolerance_) * atlas.texels_per_unit), pad_(static_cast<int>(std::ceil(slack_px_))),
        core_(core_weights(patches, options)), contribute_{patches, core_, blender_, options,
                                                           options.uv_scale / options.tile_size} {}

  SynthesisResult run();

 private:
  static std::vector<std::vector<float>> core_weights(const std::vector<Patch>& patches,
                                                      const SynthesisOptions& options);
  std::vector<char> live_tiles() const;
  std::vector<char> chart_border_faces() const;
  bool box_in_chart(const Vec2& lo, const Vec2& hi, int chart) const;
  Route route(const Patch& patch, const Tri& tri, const std::vector<char>& chart_border, std::array<Vec2, 3>& px) const;
  std::vector<Region> projected_regions(const Patch& patch, const Tri& tri, std::vector<int>& touched) const;
  TriangleBins bin_triangles() const;
  void accumulate_located(TileSums& tile, Tally& tally) const;
  void add_hits(const std::vector<PatchHit>& hits, const Vec3& p, const Vec3& n, TileSums& tile, std::size_t j,
                Tally& tally) const;
  void accumulate_binned(std::size_t index, TileSums& tile, Tally& tally) const;
  void accumulate_tails(TileSums& tile, Tally& tally) const;
  void raster_job(const Job& job, TileSums& tile) const;
  void projected_job(const Job& job, TileSums& tile) const;
  void resolve_tile(TileSums& tile, SynthesisResult& result, std::vector<char>& mask, Tally& tally) const;

  const SurfaceIndex& surface_;
  const Atlas& atlas_;
  const TexelMap& map_;
  const std::vector<Patch>& patches_;
  const Exemplar& exemplar_;
  const SynthesisOptions& options_;
  const int n_;
  const TileGrid tiles_;
  const double tolerance_;
  const Blender blender_;
  const double slack_px_;
  const int pad_;
  const std::vector<std::vector<float>> core_;
  const Contributor contribute_;
  TriangleBins bins_;
  std::unique_ptr<PatchLocator> locator_;
  std::unique_ptr<PatchCoverage> coverage_;  // texels where tails count (accumulate_tails, add_hits)
};

std::vector<std::vector<float>> Synthesizer::core_weights(const std::vector<Patch>& patches,
                                                          const SynthesisOptions& options) {
  std::vector<std::vector<float>> core(patches.size());
  tbb::parallel_for(std::size_t(0), patches.size(), [&](std::size_t p) {
    core[p].resize(patches[p].positions.size());
    for (std::size_t v = 0; v < core[p].size(); ++v)
      core[p][v] = core_weight(patches[p], v, options.radius, options.uv_scale);
  });
  return core;
}

/// Tiles holding at least one chart texel; the others are skipped.
std::vector<char> Synthesizer::live_tiles() const {
  std::vector<char> live(tiles_.count(), 0);
  tbb::parallel_for(0, tiles_.rows(), [&](int ty) {
    Rect2i{0, ty * kTile, n_, (ty + 1) * kTile}.for_each([&](int x, int y) {
      if (map_.face[texel_index(x, y, n_)] >= 0) live[tiles_.index_of(x, y)] = 1;
    });
  });
  return live;
}

/// Faces touching (by a vertex) a face of another chart. A patch triangle
/// with a corner over one of them may reach into the other chart, which its
/// atlas corners in one chart cannot show: unless its atlas box shows it
/// inside its chart, it goes the projected way.
std::vector<char> Synthesizer::chart_border_faces() const {
  const FrameMesh& mesh = surface_.mesh();
  std::vector<int> vertex_chart(mesh.positions.size(), -1);
  std::vector<char> mixed(mesh.positions.size(), 0);
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    for (int v : mesh.triangles[f]) {
      if (vertex_chart[v] < 0)
        vertex_chart[v] = atlas_.face_chart[f];
      else if (vertex_chart[v] != atlas_.face_chart[f])
        mixed[v] = 1;
    }
  }
  std::vector<char> chart_border(mesh.triangles.size(), 0);
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    for (int v : mesh.triangles[f]) chart_border[f] |= mixed[v];
  }
  return chart_border;
}

/// Whether every texel of the atlas box lo..hi, grown by a texel and the rim
/// slack, belongs to `chart` (a triangle crossing the chart's border reaches
/// the gutter).
bool Synthesizer::box_in_chart(const Vec2& lo, const Vec2& hi, int chart) const {
  const Rect2i box = texel_box(lo, hi).grown(pad_ + 1) & Rect2i{0, 0, n_, n_};
  for (int y = box.y0; y < box.y1; ++y) {
    for (int x = box.x0; x < box.x1; ++x) {
      const int f = map_.face[texel_index(x, y, n_)];
      if (!(f >= 0 && atlas_.face_chart[f] == chart)) return false;
    }
  }
  return true;
}

/// How patch triangle `tri` reaches this tile's texels: rasterised in one
/// chart when its corners (their atlas positions written to `px`) lie in one
/// chart of the tile and, next to another chart, its atlas box does too;
/// not at all when they lie in one chart of another tile, away from other
/// charts; the projected way otherwise.
Route Synthesizer::route(const Patch& patch, const Tri& tri, const std::vector<char>& chart_border,
                         std::array<Vec2, 3>& px) const {
  const int c0 = atlas_.face_chart[patch.projections[tri[0]].face];
  bool near_border = false;
  for (int k = 0; k < 3; ++k) {
    const int f = patch.projections[tri[k]].face;
    if (atlas_.face_chart[f] != c0) return Route::Projected;
    near_border = near_border || chart_border[f];
  }
  if (atlas_.charts[c0].tile != map_.tile) return near_border ? Route::Projected : Route::Elsewhere;
  for (int k = 0; k < 3; ++k) {
    const SurfacePoint& s = patch.projections[tri[k]];
    const auto& corner = atlas_.corner_px[s.face];
    px[k] = interpolate(s.bary, corner[0], corner[1], corner[2]);
  }
  const Vec2 lo = px[0].cwiseMin(px[1]).cwiseMin(px[2]), hi = px[0].cwiseMax(px[1]).cwiseMax(px[2]);
  return !near_border || box_in_chart(lo, hi, c0) ? Route::Raster : Route::Projected;
}

/// The regions of the projected fallback of patch triangle `tri`, and the
/// tiles they touch (appended to `touched`, unsorted).
std::vector<Region> Synthesizer::projected_regions(const Patch& patch, const Tri& tri,
                                                   std::vector<int>& touched) const {
  Vec3 lo = patch.positions[tri[0]], hi = lo;
  for (int k = 1; k < 3; ++k) lo = lo.cwiseMin(patch.positions[tri[k]]), hi = hi.cwiseMax(patch.positions[tri[k]]);
  // Surface triangles under the patch triangle: its box grown by the
  // in-plane slack and the chord's sagitta (a quarter of the normal
  // tolerance); the normal tolerance itself is applied per texel.
  const Vec3 grow = Vec3::Constant(0.25 * tolerance_);
  // A texel's point covers only if it lies in the prism of the
  // triangle (grown by the in-plane slack) ± tolerance along its
  // normal; on the face's plane that is inside the orthogonal
  // projection of the prism's corners, whose atlas box bounds the texels.
  const Vec3 tn = (patch.positions[tri[1]] - patch.positions[tri[0]])
                      .cross(patch.positions[tri[2]] - patch.positions[tri[0]])
                      .normalized();
  const Vec3 tu = (patch.positions[tri[1]] - patch.positions[tri[0]]).normalized(), tv = tn.cross(tu);
  const double slack = projection_slack(tolerance_);
  std::vector<Vec3> prism;
  for (int k = 0; k < 3; ++k) {
    for (int corner = 0; corner < 8; ++corner) {
      prism.emplace_back(patch.positions[tri[k]] + ((corner & 1) ? slack : -slack) * tu +
                         ((corner & 2) ? slack : -slack) * tv + ((corner & 4) ? tolerance_ : -tolerance_) * tn);
    }
  }
  std::vector<Region> regions;
  for (int f : surface_.faces_in_box(lo - grow, hi + grow)) {
    if (map_.face_start[f] == map_.face_start[f + 1]) continue;
    const Tri& ft = surface_.mesh().triangles[f];
    const Vec3& a = surface_.mesh().positions[ft[0]];
    const Vec3 e1 = surface_.mesh().positions[ft[1]] - a, e2 = surface_.mesh().positions[ft[2]] - a;
    const double d00 = e1.dot(e1), d01 = e1.dot(e2), d11 = e2.dot(e2), den = d00 * d11 - d01 * d01;
    const auto& corner = atlas_.corner_px[f];
    Vec2 rlo = Vec2::Constant(std::numeric_limits<double>::max()), rhi = -rlo;
    if (den > 0.0 && std::isfinite(tn.squaredNorm())) {
      for (const Vec3& q : prism) {  // unclamped barycentrics of q's projection on the face plane
        const Vec3 v = q - a;
        const double d20 = v.dot(e1), d21 = v.dot(e2);
        const double l1 = (d11 * d20 - d01 * d21) / den, l2 = (d00 * d21 - d01 * d20) / den;
        const Vec2 px = (1.0 - l1 - l2) * corner[0] + l1 * corner[1] + l2 * corner[2];
        rlo = rlo.cwiseMin(px), rhi = rhi.cwiseMax(px);
      }
    } else {  // degenerate: the whole face
      for (int k = 0; k < 3; ++k) rlo = rlo.cwiseMin(corner[k]), rhi = rhi.cwiseMax(corner[k]);
    }
    // Clipped to the face's own texels.
    const Vec2 flo = corner[0].cwiseMin(corner[1]).cwiseMin(corner[2]);
    const Vec2 fhi = corner[0].cwiseMax(corner[1]).cwiseMax(corner[2]);
    rlo = rlo.cwiseMax(flo), rhi = rhi.cwiseMin(fhi);
    const Region r{f, texel_box(rlo, rhi).grown(1) & Rect2i{0, 0, n_, n_}};  // a texel's margin
    if (r.rect.empty()) continue;
    regions.push_back(r);
    tiles_.for_each_tile(r.rect, [&](std::size_t tile) { touched.push_back(static_cast<int>(tile)); });
  }
  return regions;
}

/// Bins every patch triangle with weight into the atlas tiles it may touch:
/// per patch in parallel (its boundary edges and where its triangles go),
/// then merged in patch order, so every tile's list is in patch order
/// whatever the thread count.
TriangleBins Synthesizer::bin_triangles() const {
  TriangleBins bins;
  bins.jobs.resize(tiles_.count());
  bins.tri_px_base.assign(patches_.size() + 1, 0);
  for (std::size_t p = 0; p < patches_.size(); ++p)
    bins.tri_px_base[p + 1] = bins.tri_px_base[p] + patches_[p].triangles.size();
  bins.tri_px.resize(bins.tri_px_base.back());
  bins.tri_rim.assign(bins.tri_px_base.back(), 0);
  const std::vector<char> chart_border = chart_border_faces();
  std::vector<PatchBins> per_patch(patches_.size());
  tbb::parallel_for(std::size_t(0), patches_.size(), [&](std::size_t p) {
    const Patch& patch = patches_[p];
    PatchBins& out = per_patch[p];
    const std::vector<std::uint8_t> rim_bits = boundary_edge_bits(patch.triangles);
    std::copy(rim_bits.begin(), rim_bits.end(),
              bins.tri_rim.begin() + static_cast<std::ptrdiff_t>(bins.tri_px_base[p]));
    if (!(patch.kt > 0.0)) return;
    for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
      const Tri& tri = patch.triangles[t];
      if (!(patch.weight[tri[0]] > 0 || patch.weight[tri[1]] > 0 || patch.weight[tri[2]] > 0)) continue;
      // A triangle with no core weight at any corner brings only its
      // coverage tail, which counts at few texels (accumulate_tails).
      if (!(core_[p][tri[0]] > 0 || core_[p][tri[1]] > 0 || core_[p][tri[2]] > 0)) continue;
      auto& px = bins.tri_px[bins.tri_px_base[p] + t];
      const Route way = route(patch, tri, chart_border, px);
      if (way == Route::Elsewhere) continue;
      ++out.binned;
      if (way == Route::Raster) {
        // The tiles its texels (raster_job) fall in.
        const Vec2 lo = px[0].cwiseMin(px[1]).cwiseMin(px[2]), hi = px[0].cwiseMax(px[1]).cwiseMax(px[2]);
        const Job job{static_cast<int>(p), static_cast<int>(t), -1};
        tiles_.for_each_tile(texel_box(lo, hi).grown(pad_),
                             [&](std::size_t tile) { out.placed.emplace_back(static_cast<int>(tile), job); });
        continue;
      }
      ++out.projected;
      std::vector<int> touched;
      std::vector<Region> regions = projected_regions(patch, tri, touched);
      if (regions.empty()) continue;
      std::sort(touched.begin(), touched.end());
      touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
      const Job job{static_cast<int>(p), static_cast<int>(t), static_cast<int>(out.lists.size())};
      for (int tile : touched) out.placed.emplace_back(tile, job);
      out.lists.push_back(std::move(regions));
    }
  });
  merge_patch_bins(per_patch, bins);
  return bins;
}

/// The reference (SynthesisScheme::Exact): every texel of the tile projected
/// through the patch triangles near it.
void Synthesizer::accumulate_located(TileSums& tile, Tally& tally) const {
  std::vector<PatchHit> hits;
  tile.rect.for_each([&](int x, int y) {
    const std::size_t i = texel_index(x, y, n_);
    if (map_.face[i] < 0) return;
    const SurfacePoint s = surface_.at(map_.face[i], map_.bary(i));
    const Vec3 normal = surface_.normal_at(s);
    locator_->locate(s.position, normal, hits);
    add_hits(hits, s.position, normal, tile, tile.local(x, y), tally);
  });
}

/// The located hits (in patch order) of the texel at surface point `p`
/// (normal `n`). Where none brings a weight, the texel shows a patch's
/// margin rather than the exemplar's mean, the last resort, counted in
/// `tally.margin`: of the patches over it (a few texels beyond the coverage
/// tail's reach, between the points at which the tracker tests coverage),
/// the one whose centre is nearest in uv; with none over it (a hole of a
/// texel or two between patch borders), the nearest patch point within the
/// projection tolerance.
void Synthesizer::add_hits(const std::vector<PatchHit>& hits, const Vec3& p, const Vec3& n, TileSums& tile,
                           std::size_t j, Tally& tally) const {
  for (const PatchHit& h : hits) {
    const auto [w, c] = contribute_.weights(h.patch, patches_[h.patch].triangles[h.tri], h.bary);
    contribute_.add(tile.acc, j, h.patch, h.uv, w, c);
  }
  if (tile.acc.last_patch[j] >= 0) return;
  PatchHit last;
  if (!hits.empty()) {
    last = *std::min_element(hits.begin(), hits.end(), [](const PatchHit& a, const PatchHit& b) {
      return a.uv.squaredNorm() < b.uv.squaredNorm();  // ties: the lower patch index
    });
  } else if (!coverage_->nearest(p, n, tolerance_, last)) {
    return;
  }
  contribute_.add(tile.acc, j, last.patch, last.uv, kCoverageTail, 0.0);
  ++tally.margin;
}

/// Raster (SynthesisScheme::Raster): the tile's binned jobs (the triangles
/// with a core weight) in order. A projected hit waits until the patch's
/// last job: as in locate(), the patch's nearest triangle gives a texel its
/// uv and weight. A raster hit of the same patch, added at once, takes
/// precedence. Then the tails, where they count.
void Synthesizer::accumulate_binned(std::size_t index, TileSums& tile, Tally& tally) const {
  ProjectedHits& projected = tile.projected;
  for (const Job& job : bins_.jobs[index]) {
    if (job.patch != projected.patch) {
      projected.flush(contribute_, tile.acc);
      projected.patch = job.patch;
    }
    if (job.regions < 0)
      raster_job(job, tile);
    else
      projected_job(job, tile);
  }
  projected.flush(contribute_, tile.acc);
  accumulate_tails(tile, tally);
}

/// The coverage tails: a patch's tail blends only where the cores leave room
/// (λ > 0, Contributor::tail_share), a fraction of a percent of the chart
/// texels on the real caches, so the triangles that bring only a tail (about
/// half of all, the rim of every patch) are not binned. At those texels, and
/// at chart texels no binned triangle reached (a sliver face that the atlas
/// put in another chart than the faces around it lies under patch triangles
/// rasterised in the surrounding chart, and its own texels, elsewhere in
/// the atlas, would stay bare), the patches not there yet are added through
/// the reference's projection (accumulate_located's hits, found through the
/// patches' bounding spheres).
void Synthesizer::accumulate_tails(TileSums& tile, Tally& tally) const {
  std::vector<std::size_t> open;
  tile.rect.for_each([&](int x, int y) {
    if (map_.face[texel_index(x, y, n_)] < 0) return;
    const std::size_t j = tile.local(x, y);
    if (contribute_.tail_share(tile.acc.sum_core[j]) > 0.0) open.push_back(j);
  });
  if (open.empty()) return;
  // The patches already over each open texel, (texel, patch) sorted.
  std::vector<char> is_open(kTileTexels, 0);
  for (std::size_t j : open) is_open[j] = 1;
  std::vector<std::pair<std::size_t, int>> present;
  for (const Contribution& k : tile.acc.list) {
    if (is_open[k.texel]) present.emplace_back(k.texel, k.patch);
  }
  std::sort(present.begin(), present.end());
  std::vector<Vec3> points, normals;
  points.reserve(open.size());
  normals.reserve(open.size());
  for (std::size_t j : open) {
    const int x = tile.rect.x0 + static_cast<int>(j % kTile), y = tile.rect.y0 + static_cast<int>(j / kTile);
    const std::size_t i = texel_index(x, y, n_);
    const SurfacePoint s = surface_.at(map_.face[i], map_.bary(i));
    points.push_back(s.position);
    normals.push_back(surface_.normal_at(s));
  }
  coverage_->locate_each(points, normals, [&](std::size_t k, std::vector<PatchHit>& hits) {
    const std::size_t j = open[k];
    std::erase_if(hits, [&](const PatchHit& h) {
      return std::binary_search(present.begin(), present.end(), std::make_pair(j, h.patch));
    });
    add_hits(hits, points[k], normals[k], tile, j, tally);
  });
}

/// A patch triangle whose corners lie in one chart, rasterised in atlas space.
void Synthesizer::raster_job(const Job& job, TileSums& tile) const {
  const Patch& patch = patches_[job.patch];
  const Tri& tri = patch.triangles[job.tri];
  const auto& px = bins_.tri_px[bins_.tri_px_base[job.patch] + job.tri];
  const int chart = atlas_.face_chart[patch.projections[tri[0]].face];
  const Vec2 lo = px[0].cwiseMin(px[1]).cwiseMin(px[2]), hi = px[0].cwiseMax(px[1]).cwiseMax(px[2]);
  const std::uint8_t rim = bins_.tri_rim[bins_.tri_px_base[job.patch] + job.tri];
  const Rect2i box = texel_box(lo, hi).grown(rim ? pad_ : 0) & tile.rect;
  // Each row's texels are those whose centre lies within `reach` of the
  // triangle (the rim slack across a boundary edge; otherwise a margin for
  // the barycentric tolerance below), a span of the box's row.
  const double reach = (rim ? slack_px_ : 0.0) + kSpanMargin;
  for (int y = box.y0; y < box.y1; ++y) {
    double xa, xb;
    if (!slab_extent(px, 1, y + 0.5 - reach, y + 0.5 + reach, xa, xb)) continue;
    const int x0 = std::max(box.x0, static_cast<int>(std::ceil(xa - reach - 0.5)));
    const int x1 = std::min(box.x1, static_cast<int>(std::floor(xb + reach - 0.5)) + 1);
    for (int x = x0; x < x1; ++x) {
      const std::size_t i = texel_index(x, y, n_);
      if (map_.face[i] < 0 || atlas_.face_chart[map_.face[i]] != chart) continue;
      Vec3 l;
      const Vec2 centre(x + 0.5, y + 0.5);
      if (!bary2(centre, px[0], px[1], px[2], l)) continue;
      if (l.minCoeff() < -1e-9) {
        // Outside: only across the patch's own boundary edges, within the slack.
        bool across_rim = rim != 0;
        for (int j = 0; j < 3; ++j) {
          if (l[j] < -1e-9 && !(rim & (1u << ((j + 1) % 3)))) across_rim = false;
        }
        if (!across_rim) continue;
        const auto lift = [](const Vec2& v) { return Vec3(v.x(), v.y(), 0.0); };
        l = barycentric(lift(centre), lift(px[0]), lift(px[1]), lift(px[2]));
        const Vec2 closest = interpolate(l, px[0], px[1], px[2]);
        if ((closest - centre).norm() > slack_px_) continue;
      }
      const Vec2 uv = interpolate(patch.uvs, tri, l);
      const auto [w, c] = contribute_.weights(job.patch, tri, l);
      contribute_.add(tile.acc, tile.local(x, y), job.patch, uv, w, c);
    }
  }
}

/// A patch triangle of the projected fallback: the texels of its regions
/// projected onto it; hits wait in `projected` for the patch's last job.
/// Over one surface face, a texel's point and normal are affine in its
/// atlas position, so the projection is too (TriangleProjection::OnPlane).
void Synthesizer::projected_job(const Job& job, TileSums& tile) const {
  ProjectedHits& projected = tile.projected;
  const Patch& patch = patches_[job.patch];
  const Tri& tri = patch.triangles[job.tri];
  const TrianglePrism prism(patch, tri, tolerance_);
  const TriangleProjection projection(patch, tri, tolerance_);
  std::array<TrianglePrism::HalfSpace, 5> half_spaces;
  bool everything = true;
  const bool bounded = prism.half_spaces(half_spaces, everything);
  if (!bounded && !everything) return;
  // Far above the rounding of the affine map and the clamp of the texel map's
  // barycentrics, far below a texel: the span only skips texels that the
  // prism test would reject.
  const double margin = 1e-3 * tolerance_;
  const FrameMesh& mesh = surface_.mesh();
  for (const Region& r : bins_.region_lists[job.regions]) {
    const Rect2i box = r.rect & tile.rect;
    if (box.empty()) continue;
    const Tri& ft = mesh.triangles[r.face];
    const auto& corner = map_.corner_px[r.face];
    TriangleProjection::Affine3 plane, normal;
    if (!atlas_affine(corner, mesh.positions[ft[0]], mesh.positions[ft[1]], mesh.positions[ft[2]], plane)) continue;
    const std::vector<Vec3>& vn = surface_.vertex_normals();
    if (!atlas_affine(corner, vn[ft[0]], vn[ft[1]], vn[ft[2]], normal)) continue;
    const TriangleProjection::OnPlane on_plane(projection, plane, normal);
    if (!on_plane.valid()) continue;
    std::optional<RowSpans> row_spans;
    if (bounded) row_spans.emplace(plane, half_spaces, margin, corner);
    for (int y = box.y0; y < box.y1; ++y) {
      int x0 = box.x0, x1 = box.x1;
      if (row_spans && !row_spans->row(y, x0, x1)) continue;
      for (int x = x0; x < x1; ++x) {
        const std::size_t i = texel_index(x, y, n_);
        if (map_.face[i] != r.face) continue;
        const std::size_t j = tile.local(x, y);
        Vec3 l;
        double dist2;
        if (!on_plane.project(x + 0.5, y + 0.5, l, dist2)) continue;
        ProjectedHits::Hit& slot = projected.hit[j];
        if (!(dist2 < slot.dist2)) continue;  // ties: the lower triangle index, as locate()
        if (std::isinf(slot.dist2)) projected.texels.push_back(j);
        slot.dist2 = dist2;
        slot.uv = interpolate(patch.uvs, tri, l);
        std::tie(slot.w, slot.core) = contribute_.weights(job.patch, tri, l);
      }
    }
  }
}

/// Resolves Eq. 7 (or linear) for every chart texel of the tile, clamps, and
/// fills the outputs.
void Synthesizer::resolve_tile(TileSums& tile, SynthesisResult& result, std::vector<char>& mask, Tally& tally) const {
  const int nc = exemplar_.channels();
  const Accumulator& acc = tile.acc;
  contribute_.blend(acc, tile.sums);
  std::array<double, 3> sum{};
  for (int y = tile.rect.y0; y < tile.rect.y1; ++y) {
    for (int x = tile.rect.x0; x < tile.rect.x1; ++x) {
      const std::size_t i = texel_index(x, y, n_);
      if (map_.face[i] < 0) continue;
      const std::size_t j = tile.local(x, y);
      ++tally.chart;
      mask[i] = 1;
      const TexelSum& s = tile.sums[j];
      const double lambda = contribute_.tail_share(acc.sum_core[j]);
      for (int c = 0; c < nc; ++c) sum[c] = s.sum[c] + lambda * s.tail_sum[c];
      const double sum_w = s.sum_w + lambda * s.tail_w;
      const double sum_w2 = s.sum_w2 + 2.0 * lambda * s.cross + lambda * lambda * s.tail_w2;
      if (options_.aov) {
        result.weight.pixels[i] = static_cast<float>(sum_w);
        result.count.pixels[i] = static_cast<float>(s.count + (lambda > 0.0 ? s.tail_count : 0));
        if (s.best_patch >= 0) {
          const auto rgb = id_color(patches_[s.best_patch].id);
          for (int c = 0; c < 3; ++c) result.patch.pixel(i)[c] = rgb[c] / 255.0f;
        }
      }
      if (!(sum_w > 0.0)) {
        ++tally.bare;
        for (int c = 0; c < nc; ++c) result.color.pixel(i)[c] = exemplar_.mean()[c];
        continue;
      }
      tally.clamped += blender_.resolve(sum.data(), sum_w, sum_w2, result.color.pixel(i));
      tally.dominant += s.best_w >= kDominantWeight * sum_w;
    }
  }
}

SynthesisResult Synthesizer::run() {
  const int nc = exemplar_.channels();
  SynthesisResult result = SynthesisResult::blank(n_, nc, options_.aov);
  const std::size_t texel_count = static_cast<std::size_t>(n_) * n_;
  const std::size_t tile_count = tiles_.count();
  const std::vector<char> tile_live = live_tiles();
  coverage_ = std::make_unique<PatchCoverage>(patches_, tolerance_);
  if (options_.scheme == SynthesisScheme::Exact) {
    locator_ = std::make_unique<PatchLocator>(patches_, tolerance_);
  } else {
    bins_ = bin_triangles();
    result.binned_triangles = bins_.binned;
    result.projected_triangles = bins_.projected;
  }
  // Per tile, in parallel: accumulate into tile-local sums (each texel's
  // contributions in patch order), then resolve.
  std::vector<char> mask(texel_count, 0);
  std::vector<Tally> tally(tile_count);
  // One workspace per thread: a tile's body runs no parallel work of its
  // own, so a thread never takes up another tile while in one.
  tbb::enumerable_thread_specific<TileSums> workspace;
  tbb::parallel_for(std::size_t(0), tile_count, [&](std::size_t index) {
    if (!tile_live[index]) return;
    TileSums& tile = workspace.local();
    tile.start(tiles_.rect(index));
    if (locator_)
      accumulate_located(tile, tally[index]);
    else
      accumulate_binned(index, tile, tally[index]);
    resolve_tile(tile, result, mask, tally[index]);
  });
  for (const Tally& t : tally) {
    result.chart_texels += t.chart;
    result.uncovered_texels += t.bare;
    result.margin_texels += t.margin;
    result.clamped_texels += t.clamped;
    result.dominant_texels += t.dominant;
  }
  dilate(result.color, mask, 8);
  return result;
}

}  // namespace

SynthesisResult synthesize(const SurfaceIndex& surface, const Atlas& atlas, const TexelMap& map,
                           const std::vector<Patch>& patches, const Exemplar& exemplar,
                           const SynthesisOptions& options) {
  FLUIDTEX_CHECK_GT(options.tile_size, 0.0);
  FLUIDTEX_CHECK_GT(options.radius, 0.0);
  return Synthesizer(surface, atlas, map, patches, exemplar, options).run();
}

}  // namespace fluidtex
