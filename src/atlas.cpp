#include "fluidtex/atlas.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>

#include <Eigen/Eigenvalues>
#include <oneapi/tbb/parallel_for.h>

#include "fluidtex/disk_region.h"
#include "fluidtex/error.h"
#include "fluidtex/parameterization.h"

namespace fluidtex {

void AtlasOptions::validate() const {
  if (size < 16 || size > 32768) throw InputError("", "--atlas-size must be in [16, 32768]");
  if (gutter < 1 || gutter > 64) throw InputError("", "--gutter must be in [1, 64]");
  if (!(normal_cone > -1.0 && normal_cone < 1.0)) throw InputError("", "chart normal cone must be in (-1, 1)");
}

namespace {

/// A chart flattened in scene units, before packing.
struct FlatChart {
  std::vector<std::array<Vec2, 3>> corners;  // per face of the chart
  Vec2 min = Vec2::Zero(), max = Vec2::Zero();
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
    const double a3 = 0.5 * (disk.positions[t[1]] - disk.positions[t[0]]).cross(disk.positions[t[2]] - disk.positions[t[0]]).norm();
    if (a3 > 0.0 && a_uv > 0.0) {
      weighted += a3 * std::max(a_uv / a3, a3 / a_uv);
      total += a3;
    }
  }
  stretch = total > 0.0 ? weighted / total : 1.0;  // area-weighted mean
  return true;
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
  return out;
}

/// Skyline bottom-left packing of rectangles into a square of side `size`,
/// tallest first, each placed where its top ends lowest (then leftmost),
/// upright or turned by 90°. Fills `origin` and `turned`; false when they do
/// not fit. Deterministic (ties by index).
bool pack_skyline(const std::vector<Eigen::Vector2i>& extent, int size, std::vector<Eigen::Vector2i>& origin,
                  std::vector<char>& turned) {
  std::vector<int> order(extent.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    const int ha = std::max(extent[a].x(), extent[a].y()), hb = std::max(extent[b].x(), extent[b].y());
    return ha > hb;
  });
  struct Segment {
    int x, y, w;
  };
  std::vector<Segment> sky{{0, 0, size}};
  origin.assign(extent.size(), Eigen::Vector2i::Zero());
  turned.assign(extent.size(), 0);
  for (int i : order) {
    int best_top = std::numeric_limits<int>::max(), best_x = 0, best_seg = -1;
    bool best_turn = false;
    for (int turn = 0; turn < 2; ++turn) {
      const int w = turn ? extent[i].y() : extent[i].x();
      const int h = turn ? extent[i].x() : extent[i].y();
      if (w > size) continue;
      for (std::size_t s = 0; s < sky.size(); ++s) {
        const int x = sky[s].x;
        if (x + w > size) break;
        // The rectangle rests on the highest segment it spans.
        int y = 0, covered = 0;
        for (std::size_t k = s; k < sky.size() && covered < w; ++k) {
          y = std::max(y, sky[k].y);
          covered += sky[k].w - (k == s ? 0 : 0);
        }
        if (y + h > size) continue;
        if (y + h < best_top || (y + h == best_top && x < best_x)) {
          best_top = y + h, best_x = x, best_seg = static_cast<int>(s), best_turn = turn;
        }
      }
    }
    if (best_seg < 0) return false;
    const int w = best_turn ? extent[i].y() : extent[i].x();
    const int h = best_turn ? extent[i].x() : extent[i].y();
    int y = 0, covered = 0;
    for (std::size_t k = best_seg; k < sky.size() && covered < w; ++k) {
      y = std::max(y, sky[k].y);
      covered += sky[k].w;
    }
    origin[i] = Eigen::Vector2i(best_x, y);
    turned[i] = best_turn;
    // New skyline: [best_x, best_x + w) at height y + h; trim what it covers.
    std::vector<Segment> next;
    for (const Segment& seg : sky) {
      const int a = seg.x, b = seg.x + seg.w;
      if (b <= best_x || a >= best_x + w) {
        next.push_back(seg);
        continue;
      }
      if (a < best_x) next.push_back({a, seg.y, best_x - a});
      if (b > best_x + w) next.push_back({best_x + w, seg.y, b - (best_x + w)});
    }
    next.push_back({best_x, y + h, w});
    std::sort(next.begin(), next.end(), [](const Segment& p, const Segment& q) { return p.x < q.x; });
    // Merge neighbours at the same height.
    sky.clear();
    for (const Segment& seg : next) {
      if (!sky.empty() && sky.back().y == seg.y && sky.back().x + sky.back().w == seg.x) sky.back().w += seg.w;
      else sky.push_back(seg);
    }
  }
  return true;
}

}  // namespace

Atlas build_atlas(const SurfaceIndex& surface, const AtlasOptions& options) {
  options.validate();
  const FrameMesh& mesh = surface.mesh();
  const std::size_t nf = mesh.triangles.size();
  Atlas atlas;
  atlas.size = options.size;
  atlas.face_chart.assign(nf, -1);
  atlas.corner_px.assign(nf, {});

  // 1–2. Segment into disk-like charts bounded by a normal cone, flatten
  // each (in parallel, each into its own slot), and segment again, smaller,
  // the faces of charts LSCM could not flatten or flattened with too much
  // area distortion; single faces are always flat.
  std::vector<std::vector<int>> final_faces;
  std::vector<FlatChart> final_flat;
  std::vector<double> final_stretch;
  std::vector<int> pending(nf);
  std::iota(pending.begin(), pending.end(), 0);
  std::size_t max_faces = options.max_chart_faces;
  std::vector<char> assigned(nf, 0);
  while (!pending.empty()) {
    std::vector<std::vector<int>> chart_faces;
    for (int seed : pending) {
      if (assigned[seed]) continue;
      const Vec3 n0 = surface.face_normals()[seed];
      const Tri& st = mesh.triangles[seed];
      const Vec3 c0 = (mesh.positions[st[0]] + mesh.positions[st[1]] + mesh.positions[st[2]]) / 3.0;
      DiskRegionOptions region;
      region.accept = [&](int f) { return !assigned[f] && surface.face_normals()[f].dot(n0) > options.normal_cone; };
      region.priority = [&](int f) {
        const Tri& t = mesh.triangles[f];
        return ((mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0 - c0).squaredNorm();
      };
      region.max_faces = max_faces;
      std::vector<int> faces = grow_disk_region(surface, seed, region);
      for (int f : faces) assigned[f] = 1;
      chart_faces.push_back(std::move(faces));
    }
    std::vector<FlatChart> flat(chart_faces.size());
    std::vector<double> stretch(chart_faces.size(), 1.0);
    std::vector<char> ok(chart_faces.size(), 1);
    tbb::parallel_for(std::size_t(0), chart_faces.size(), [&](std::size_t c) {
      if (chart_faces[c].size() == 1) flat[c] = flat_face(mesh, chart_faces[c][0]);
      else ok[c] = flatten_chart(mesh, chart_faces[c], flat[c], stretch[c]) && stretch[c] <= options.max_stretch;
    });
    pending.clear();
    for (std::size_t c = 0; c < chart_faces.size(); ++c) {
      if (ok[c]) {
        final_faces.push_back(std::move(chart_faces[c]));
        final_flat.push_back(std::move(flat[c]));
        final_stretch.push_back(stretch[c]);
        continue;
      }
      ++atlas.failed_charts;
      for (int f : chart_faces[c]) {
        assigned[f] = 0;
        pending.push_back(f);
      }
    }
    std::sort(pending.begin(), pending.end());
    max_faces = std::max<std::size_t>(1, max_faces / 4);
  }

  // 3. Common density: the largest (bisection) whose shelf packing fits.
  double area3 = 0.0;
  for (double a : surface.face_areas()) area3 += a;
  const int n = options.size;
  const int pad = 2 * options.gutter;
  auto extents_for = [&](double density) {
    std::vector<Eigen::Vector2i> ext(final_flat.size());
    for (std::size_t c = 0; c < final_flat.size(); ++c) {
      const Vec2 span = (final_flat[c].max - final_flat[c].min) * density;
      ext[c] = Eigen::Vector2i(static_cast<int>(std::ceil(span.x())) + pad + 1, static_cast<int>(std::ceil(span.y())) + pad + 1);
    }
    return ext;
  };
  std::vector<Eigen::Vector2i> origin;
  std::vector<char> turned;
  double lo = 0.0, hi = area3 > 0.0 ? std::sqrt(static_cast<double>(n) * n / area3) : 1.0;  // 100% would be this
  for (int iter = 0; iter < 30; ++iter) {
    const double mid = 0.5 * (lo + hi);
    if (pack_skyline(extents_for(mid), n, origin, turned)) lo = mid;
    else hi = mid;
  }
  if (!(lo > 0.0)) throw InternalError("atlas: " + std::to_string(final_flat.size()) + " charts do not fit in " +
                                       std::to_string(n) + "² texels; raise --atlas-size");
  atlas.texels_per_unit = lo;
  const std::vector<Eigen::Vector2i> extent = extents_for(lo);
  pack_skyline(extent, n, origin, turned);

  // 4. Corner positions in texels.
  atlas.charts.resize(final_faces.size());
  double chart_area_px = 0.0;
  for (std::size_t c = 0; c < final_faces.size(); ++c) {
    Chart& chart = atlas.charts[c];
    chart.faces = std::move(final_faces[c]);
    chart.origin = origin[c];
    chart.extent = turned[c] ? Eigen::Vector2i(extent[c].y(), extent[c].x()) : extent[c];
    chart.stretch = final_stretch[c];
    // Turned charts are rotated by 90° (x, y) -> (max.y − y, x − min.x).
    const FlatChart& fc = final_flat[c];
    auto place = [&](const Vec2& p) {
      const Vec2 local = turned[c] ? Vec2(fc.max.y() - p.y(), p.x() - fc.min.x()) : Vec2(p - fc.min);
      return Vec2(local * lo + origin[c].cast<double>() + Vec2::Constant(options.gutter + 0.5));
    };
    for (std::size_t i = 0; i < chart.faces.size(); ++i) {
      const int f = chart.faces[i];
      atlas.face_chart[f] = static_cast<int>(c);
      for (int k = 0; k < 3; ++k) atlas.corner_px[f][k] = place(fc.corners[i][k]);
      chart.area3 += surface.face_areas()[f];
    }
    chart_area_px += chart.area3 * lo * lo;
  }
  atlas.packing_efficiency = chart_area_px / (static_cast<double>(n) * n);
  return atlas;
}

UVMesh atlas_uv_mesh(const SurfaceIndex& surface, const Atlas& atlas) {
  const FrameMesh& mesh = surface.mesh();
  UVMesh out;
  out.positions = mesh.positions;
  out.normals = surface.vertex_normals();
  out.triangles = mesh.triangles;
  out.uv_triangles.resize(mesh.triangles.size());
  std::unordered_map<std::uint64_t, int> shared;  // (vertex, chart) -> uv index
  const double inv = 1.0 / atlas.size;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t key = (static_cast<std::uint64_t>(mesh.triangles[f][k]) << 32) |
                                static_cast<std::uint32_t>(atlas.face_chart[f]);
      auto [it, inserted] = shared.emplace(key, static_cast<int>(out.uvs.size()));
      if (inserted) {
        const Vec2& p = atlas.corner_px[f][k];
        out.uvs.emplace_back(p.x() * inv, 1.0 - p.y() * inv);
      }
      out.uv_triangles[f][k] = it->second;
    }
  }
  return out;
}

}  // namespace fluidtex
