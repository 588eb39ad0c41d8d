// Flat example scenes (rotation, split, merge, stream, stream-rock), scene dispatch and the PLY
// writer. The 3D `drop` scene lives in scene_drop.cpp (OpenVDB).
//
// All flat scenes lie in the z = 0 plane with counter-clockwise triangles
// (normals +z). Velocities are analytic, evaluated at the vertices, in scene
// units per second; frame f is at time t = (f - 1) / fps.
#include "fluidtex/scenes/scenes.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <numbers>
#include <span>
#include <string>
#include <unordered_map>

#include <tbb/parallel_for.h>

#include "fluidtex/io/ply_writer.h"
#include "fluidtex/io/vdb_io.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/options.h"
#include "scene_drop.h"
#include "scene_pour.h"
#include "scene_volume.h"

namespace fluidtex {

namespace {

constexpr double kPi = std::numbers::pi;

// ---------------------------------------------------------------------------
// Marching triangles on a regular grid: the triangulated inside {F < 0} of a
// roughly distance-like implicit function F (|grad F| ~ 1 near F = 0).
// Each grid cell is split into two triangles (alternating diagonals); every
// grid triangle is clipped against F = 0 with crossing points on grid edges
// shared between neighbours, so the result is a conforming mesh whose
// outline follows the contour. Node values closer than `snap` to zero are
// pushed away from it, which bounds the crossing parameter away from the
// nodes and so rules out sliver triangles. Crossings start from the linear
// interpolation of node values and are refined with a few regula-falsi steps
// on the exact F.
// ---------------------------------------------------------------------------
using Implicit2D = std::function<double(const Vec2&)>;

/// Where F crosses zero between pa (F = fa) and pb (F = fb), as t in [0, 1]:
/// Illinois regula falsi on the exact function, six steps; `guess` when the
/// ends do not bracket a zero.
double zero_crossing(const Implicit2D& F, const Vec2& pa, const Vec2& pb, double fa, double fb, double guess) {
  if ((fa < 0.0) == (fb < 0.0)) return guess;
  double t = guess, t0 = 0.0, t1 = 1.0;
  int side = 0;
  for (int iter = 0; iter < 6; ++iter) {
    t = (t0 * fb - t1 * fa) / (fb - fa);
    const double ft = F(pa + t * (pb - pa));
    if ((ft < 0.0) == (fa < 0.0)) {
      t0 = t, fa = ft;
      if (side == -1) fb *= 0.5;
      side = -1;
    } else {
      t1 = t, fb = ft;
      if (side == 1) fa *= 0.5;
      side = 1;
    }
  }
  return t;
}

/// The clipped piece of a grid triangle (3 or 4 vertices, counter-clockwise)
/// as triangles: a quad split along its shorter diagonal.
void add_polygon(FrameMesh& mesh, const int* poly, int count) {
  if (count == 3) {
    mesh.triangles.push_back({poly[0], poly[1], poly[2]});
  } else if (count == 4) {
    const auto& P = mesh.positions;
    if ((P[poly[0]] - P[poly[2]]).squaredNorm() <= (P[poly[1]] - P[poly[3]]).squaredNorm()) {
      mesh.triangles.push_back({poly[0], poly[1], poly[2]});
      mesh.triangles.push_back({poly[0], poly[2], poly[3]});
    } else {
      mesh.triangles.push_back({poly[0], poly[1], poly[3]});
      mesh.triangles.push_back({poly[1], poly[2], poly[3]});
    }
  }
}

/// Meshes {F < 0} on a grid of spacing h over a box: the values at the grid
/// nodes (snapped away from 0 by 0.08 h, so that no sliver is cut), and per
/// triangle of the grid the clipped polygon, its vertices shared between
/// neighbouring triangles (a node's, or an edge's zero crossing).
class ContourMesher {
 public:
  ContourMesher(const Implicit2D& F, const Vec2& lo, const Vec2& hi, double h) : F_(F), h_(h) {
    // Even cell counts keep the grid (and its diagonal pattern) mirror
    // symmetric about the box centre.
    auto cells = [&](double extent) {
      const int n = std::max(2, static_cast<int>(std::ceil(extent / h)));
      return n + n % 2;
    };
    nx_ = cells(hi.x() - lo.x()), ny_ = cells(hi.y() - lo.y());
    origin_ = 0.5 * (lo + hi) - 0.5 * h * Vec2(nx_, ny_);
    stride_ = nx_ + 1;
    const double snap = 0.08 * h;
    exact_.resize(static_cast<std::size_t>(stride_) * (ny_ + 1));
    value_.resize(exact_.size());
    for (std::size_t n = 0; n < exact_.size(); ++n) {
      exact_[n] = F(node_pos(static_cast<int>(n)));
      const double v = exact_[n];
      value_[n] = v < 0.0 ? std::min(v, -snap) : std::max(v, snap);
    }
    node_vertex_.assign(exact_.size(), -1);
  }

  FrameMesh mesh() {
    for (int j = 0; j < ny_; ++j) {
      for (int i = 0; i < nx_; ++i) {
        const int n00 = j * stride_ + i, n10 = n00 + 1, n01 = n00 + stride_, n11 = n01 + 1;
        if ((i + j) % 2 == 0) {
          clip_triangle(n00, n10, n11);
          clip_triangle(n00, n11, n01);
        } else {
          clip_triangle(n00, n10, n01);
          clip_triangle(n10, n11, n01);
        }
      }
    }
    return std::move(mesh_);
  }

 private:
  Vec2 node_pos(int n) const { return Vec2(origin_.x() + h_ * (n % stride_), origin_.y() + h_ * (n / stride_)); }

  int add_vertex(const Vec2& p) {
    mesh_.positions.emplace_back(p.x(), p.y(), 0.0);
    return static_cast<int>(mesh_.positions.size()) - 1;
  }

  int vertex_at_node(int n) {
    if (node_vertex_[n] < 0) node_vertex_[n] = add_vertex(node_pos(n));
    return node_vertex_[n];
  }

  int vertex_on_edge(int a, int b) {
    if (a > b) std::swap(a, b);  // canonical orientation: same point from both sides
    const std::uint64_t key = (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
    auto it = edge_vertex_.find(key);
    if (it != edge_vertex_.end()) return it->second;
    const Vec2 pa = node_pos(a), pb = node_pos(b);
    const double t =
        std::clamp(zero_crossing(F_, pa, pb, exact_[a], exact_[b], value_[a] / (value_[a] - value_[b])), 0.06, 0.94);
    const int v = add_vertex(pa + t * (pb - pa));
    edge_vertex_.emplace(key, v);
    return v;
  }

  void clip_triangle(int a, int b, int c) {
    const int nodes[3] = {a, b, c};
    int poly[4];
    int count = 0;
    for (int k = 0; k < 3; ++k) {
      const int p = nodes[k], q = nodes[(k + 1) % 3];
      const bool pin = value_[p] < 0.0, qin = value_[q] < 0.0;
      if (pin) poly[count++] = vertex_at_node(p);
      if (pin != qin) poly[count++] = vertex_on_edge(p, q);
    }
    add_polygon(mesh_, poly, count);
  }

  const Implicit2D& F_;
  double h_;
  int nx_ = 0, ny_ = 0, stride_ = 0;
  Vec2 origin_;
  std::vector<double> exact_, value_;
  std::vector<int> node_vertex_;
  std::unordered_map<std::uint64_t, int> edge_vertex_;
  FrameMesh mesh_;
};

FrameMesh mesh_implicit_2d(const Implicit2D& F, const Vec2& lo, const Vec2& hi, double h) {
  return ContourMesher(F, lo, hi, h).mesh();
}

void set_velocities(FrameMesh& mesh, const std::function<Vec2(const Vec2&)>& velocity) {
  mesh.velocities.resize(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const Vec2 u = velocity(mesh.positions[v].head<2>());
    mesh.velocities[v] = Vec3(u.x(), u.y(), 0.0);
  }
}

// ---------------------------------------------------------------------------
// rotation (Fig. 8): unit disc, rigid rotation, a quarter turn in 4 s.
// Concentric rings at spacing h = 2 / resolution; ring k has 6k vertices, so
// triangles are near-equilateral and the mesh has 6 n^2 faces (n rings).
// ---------------------------------------------------------------------------
constexpr double kRotationOmega = (kPi / 2.0) / 4.0;  // rad / s

FrameMesh make_rotation(const SceneOptions& options) {
  const int rings = std::max(2, (options.resolution + 1) / 2);
  FrameMesh mesh;
  mesh.positions.emplace_back(0.0, 0.0, 0.0);
  int inner_start = 0, inner_count = 1;
  for (int k = 1; k <= rings; ++k) {
    const double radius = static_cast<double>(k) / rings;
    const int outer_count = 6 * k;
    const int outer_start = static_cast<int>(mesh.positions.size());
    for (int j = 0; j < outer_count; ++j) {
      const double angle = 2.0 * kPi * j / outer_count;
      mesh.positions.emplace_back(radius * std::cos(angle), radius * std::sin(angle), 0.0);
    }
    // Zip the two rings together by angular parameter.
    auto inner = [&](int i) { return inner_start + i % inner_count; };
    auto outer = [&](int j) { return outer_start + j % outer_count; };
    int i = 0, j = 0;
    const int inner_steps = inner_count == 1 ? 0 : inner_count;
    while (i < inner_steps || j < outer_count) {
      const double t_outer = static_cast<double>(j + 1) / outer_count;
      const double t_inner = static_cast<double>(i + 1) / inner_count;
      if (j < outer_count && (i >= inner_steps || t_outer <= t_inner)) {
        mesh.triangles.push_back({inner(i), outer(j), outer(j + 1)});
        ++j;
      } else {
        mesh.triangles.push_back({inner(i), outer(j), inner(i + 1)});
        ++i;
      }
    }
    inner_start = outer_start;
    inner_count = outer_count;
  }
  set_velocities(mesh, [](const Vec2& p) { return Vec2(-kRotationOmega * p.y(), kRotationOmega * p.x()); });
  return mesh;
}

// ---------------------------------------------------------------------------
// split (Fig. 9, "split Y"): potential flow past the tip of a wedge-shaped
// divider. With z = x + iy and the complex potential W(z) = -U (iz)^n,
// n = pi / (pi - beta), the stream function is psi = -U r^n sin(n phi), phi
// the polar angle measured from the -y axis (phi in [-pi/n, pi/n]). The fluid
// domain is {|psi| <= U Q} (outer walls are streamlines), minus the divider
// wedge |phi| > pi/n (its faces are the streamline psi = 0), cut by the
// circle r <= R. Fluid enters through the stem at the bottom (moving +y),
// stagnates at the divider tip (origin) and leaves through two branches that
// point at +-beta from the vertical. The flow is exactly divergence free and
// tangent to all walls; speed = U n r^(n-1) (about 0.9 units/s at r = 1,
// ~0.5 domain widths per second).
// ---------------------------------------------------------------------------
struct SplitFlow {
  double beta = kPi / 6.0;  // branch half-angle from the vertical
  double n = kPi / (kPi - kPi / 6.0);
  double U = 0.75;  // speed scale, units / s
  double Q = 0.32;  // wall stream-function level (in units of U)
  double R = 1.0;   // inflow / outflow cut radius

  static double phi(const Vec2& p) { return std::atan2(p.x(), -p.y()); }

  double psi(const Vec2& p) const {
    return -std::pow(p.norm(), n) * std::sin(n * phi(p));  // divided by U
  }
  Vec2 velocity(const Vec2& p) const {
    // u - i v = dW/dz = -U n i (iz)^(n-1).
    const std::complex<double> iz(-p.y(), p.x());
    if (std::abs(iz) < 1e-300) return Vec2::Zero();
    const std::complex<double> d = -U * n * std::complex<double>(0.0, 1.0) * std::pow(iz, n - 1.0);
    return Vec2(d.real(), -d.imag());
  }
  double implicit(const Vec2& p) const {
    const double r = p.norm();
    const double grad = std::max(n * std::pow(r, n - 1.0), 1e-6);  // |grad psi| / U
    const double wall = (std::abs(psi(p)) - Q) / grad;
    const double wedge = r * std::sin(std::clamp(std::abs(phi(p)) - kPi / n, -kPi / 2, kPi / 2));
    const double cut = r - R;
    return std::max({wall, wedge, cut});
  }
};

FrameMesh make_split(const SceneOptions& options) {
  const SplitFlow flow;
  const Vec2 lo(-0.75, -1.02), hi(0.75, 0.9);
  const double h = (hi - lo).maxCoeff() / options.resolution;
  FrameMesh mesh = mesh_implicit_2d([&](const Vec2& p) { return flow.implicit(p); }, lo, hi, h);
  set_velocities(mesh, [&](const Vec2& p) { return flow.velocity(p); });
  return mesh;
}

// ---------------------------------------------------------------------------
// merge (Fig. 10): a 2D metaball region f(p) = sum_i exp(-|p - c_i|^2 / s^2)
// >= tau with two blobs at c_{1,2} = +-d(t) (cos a(t), sin a(t)). The
// half-distance d(t) = d0 + (d1 - d0) sin^2(pi t / T) (T: sequence
// duration) makes the region one component at the start, two in the middle
// and one again at the end; the pair turns by a(t) = A t / T.
// Velocity: each blob's material moves with the blob and turns with the
// pair, v_i(p) = c_i' + a' perp(p - c_i); the blend v_b = sum w_i v_i with
// w_i = f_i / f, then corrected along grad f so that every iso-contour is
// carried exactly: v = v_b - (df/dt + v_b . grad f) grad f / (|grad f|^2 + eps^2).
// The correction vanishes where one blob dominates and acts in the neck.
// ---------------------------------------------------------------------------
struct MergeFlow {
  double sigma = 0.5, tau = 0.5;
  double d0 = 0.3, d1 = 0.85;  // closest / farthest half-distance
  double turn = kPi / 3.0;     // total turn of the pair over the sequence
  double T = 1.0;              // sequence duration, s

  double d(double t) const { return d0 + (d1 - d0) * std::pow(std::sin(kPi * t / T), 2); }
  double d_dot(double t) const { return (d1 - d0) * kPi / T * std::sin(2.0 * kPi * t / T); }
  double omega() const { return turn / T; }

  void centres(double t, Vec2 c[2], Vec2 c_dot[2]) const {
    const double a = omega() * t;
    const Vec2 dir(std::cos(a), std::sin(a)), perp(-std::sin(a), std::cos(a));
    const double dd = d(t), ddot = d_dot(t);
    for (int i = 0; i < 2; ++i) {
      const double s = i == 0 ? 1.0 : -1.0;
      c[i] = s * dd * dir;
      c_dot[i] = s * (ddot * dir + dd * omega() * perp);
    }
  }
  double implicit(const Vec2& p, double t) const {
    Vec2 c[2], cd[2];
    centres(t, c, cd);
    double f = 0.0;
    Vec2 grad = Vec2::Zero();
    for (const Vec2& ci : c) {
      const double fi = std::exp(-(p - ci).squaredNorm() / (sigma * sigma));
      f += fi;
      grad += -2.0 * fi / (sigma * sigma) * (p - ci);
    }
    return (tau - f) / std::max(grad.norm(), 0.25);
  }
  Vec2 velocity(const Vec2& p, double t) const {
    Vec2 c[2], cd[2];
    centres(t, c, cd);
    double f = 0.0, df_dt = 0.0;
    Vec2 grad = Vec2::Zero(), vb = Vec2::Zero();
    for (int i = 0; i < 2; ++i) {
      const Vec2 r = p - c[i];
      const double fi = std::exp(-r.squaredNorm() / (sigma * sigma));
      const Vec2 gi = -2.0 * fi / (sigma * sigma) * r;
      f += fi;
      grad += gi;
      df_dt += -gi.dot(cd[i]);
      vb += fi * (cd[i] + omega() * Vec2(-r.y(), r.x()));
    }
    if (f <= 0.0) return Vec2::Zero();
    vb /= f;
    const double eps2 = 0.3 * 0.3;
    return vb - (df_dt + vb.dot(grad)) / (grad.squaredNorm() + eps2) * grad;
  }
};

FrameMesh make_merge(int frame, const SceneOptions& options) {
  MergeFlow flow;
  flow.T = options.duration();
  const double t = options.time_of(frame);
  const Vec2 lo(-1.4, -1.4), hi(1.4, 1.4);
  const double h = (hi - lo).maxCoeff() / options.resolution;
  FrameMesh mesh = mesh_implicit_2d([&](const Vec2& p) { return flow.implicit(p, t); }, lo, hi, h);
  set_velocities(mesh, [&](const Vec2& p) { return flow.velocity(p, t); });
  return mesh;
}

// ---------------------------------------------------------------------------
// stream and stream-rock: liquid that enters a fixed window at one edge and
// leaves it at the other, every frame (an inflow and an outflow). The sheet
// is the same every frame; the liquid moves through it in +x at about
// kStreamSpeed units/s, so surface is made at the inflow edge x = -L and
// destroyed at the outflow edge x = +L, and nowhere else (both flows are
// divergence free, so every other part of the sheet keeps its area).
//  - stream: the channel [-L, L] x [-W, W], a uniform flow u = U, v = 0:
//    the liquid moves rigidly, so a patch only ever meets the two edges.
//  - stream-rock: potential flow past a cylinder of radius a at the origin
//    (a rock standing out of the water), psi = U y (1 - a^2 / r^2); the
//    walls are the streamlines |psi| = U W, so they bulge around the rock,
//    and the flow stagnates at its upstream and downstream points.
// ---------------------------------------------------------------------------
constexpr double kStreamSpeed = 1.2;       // U, units / s: 0.05 units a frame at 24 fps
constexpr double kStreamHalfLength = 1.5;  // L
constexpr double kStreamHalfWidth = 0.5;   // W
constexpr double kStreamRock = 0.2;        // a

FrameMesh make_stream(const SceneOptions& options) {
  const double L = kStreamHalfLength, W = kStreamHalfWidth, U = kStreamSpeed;
  const Vec2 lo(-L, -W), hi(L, W);
  const double h = 2.0 * L / options.resolution;
  FrameMesh mesh = mesh_implicit_2d([&](const Vec2& p) { return std::max(std::abs(p.x()) - L, std::abs(p.y()) - W); },
                                    lo - Vec2::Constant(h), hi + Vec2::Constant(h), h);
  set_velocities(mesh, [&](const Vec2&) { return Vec2(U, 0.0); });
  return mesh;
}

struct RockFlow {
  double U = kStreamSpeed, a = kStreamRock, W = kStreamHalfWidth, L = kStreamHalfLength;

  Vec2 velocity(const Vec2& p) const {
    const double r2 = std::max(p.squaredNorm(), 1e-12), r4 = r2 * r2;
    const double a2 = a * a;
    return Vec2(U * (1.0 - a2 * (p.x() * p.x() - p.y() * p.y()) / r4), -2.0 * U * a2 * p.x() * p.y() / r4);
  }
  double implicit(const Vec2& p) const {
    const double r2 = std::max(p.squaredNorm(), 1e-12);
    const double psi = p.y() * (1.0 - a * a / r2);              // divided by U
    const double grad = std::max(velocity(p).norm() / U, 0.3);  // |grad psi| / U
    const double wall = (std::abs(psi) - W) / grad;
    return std::max({wall, a - std::sqrt(r2), std::abs(p.x()) - L});
  }
};

FrameMesh make_stream_rock(const SceneOptions& options) {
  const RockFlow flow;
  const Vec2 lo(-flow.L, -0.65), hi(flow.L, 0.65);
  const double h = 2.0 * flow.L / options.resolution;
  FrameMesh mesh = mesh_implicit_2d([&](const Vec2& p) { return flow.implicit(p); }, lo - Vec2::Constant(h),
                                    hi + Vec2::Constant(h), h);
  set_velocities(mesh, [&](const Vec2& p) { return flow.velocity(p); });
  return mesh;
}

const char* const kSceneNames[] = {"rotation", "split", "merge", "drop", "pour", "stream", "stream-rock"};
const char* const kVolumeScenes[] = {"drop", "pour"};  // closed 3D surfaces: a level set holds them

std::string name_list(std::span<const char* const> names) {
  std::string list;
  for (const char* name : names) list += (list.empty() ? "" : ", ") + std::string(name);
  return list;
}

bool listed(std::span<const char* const> names, const std::string& scene) {
  return std::any_of(names.begin(), names.end(), [&](const char* name) { return scene == name; });
}

void validate(const std::string& scene, const SceneOptions& options) {
  if (!listed(kSceneNames, scene)) {
    throw InputError("", "unknown scene '" + scene + "' (known: " + name_list(kSceneNames) + ")");
  }
  if (options.frames < 1) {
    throw InputError("", "invalid frame count " + std::to_string(options.frames) + " (must be >= 1)");
  }
  if (options.resolution < 4) {
    throw InputError("", "invalid resolution " + std::to_string(options.resolution) + " (must be >= 4)");
  }
  if (!(options.fps > 0.0) || !std::isfinite(options.fps)) {
    throw InputError("", "invalid fps " + std::to_string(options.fps) + " (must be > 0)");
  }
  if (options.format != "ply" && options.format != "vdb") {
    throw InputError("", "unknown format '" + options.format + "' (known: ply, vdb)");
  }
  if (options.format == "vdb" && !listed(kVolumeScenes, scene)) {
    throw InputError("", "scene '" + scene +
                             "' is a flat open sheet, which a level set cannot hold: --format vdb "
                             "is for the 3D scenes (" +
                             name_list(kVolumeScenes) + ")");
  }
  if (options.staggered && options.format != "vdb") throw InputError("", "--staggered needs --format vdb");
}

}  // namespace

std::vector<std::string> scene_names() { return {std::begin(kSceneNames), std::end(kSceneNames)}; }

FrameMesh make_scene_frame(const std::string& scene, int frame, const SceneOptions& options) {
  validate(scene, options);
  if (frame < 1 || frame > options.frames) {
    throw InputError("", "frame " + std::to_string(frame) + " outside 1-" + std::to_string(options.frames));
  }
  if (scene == "rotation") return make_rotation(options);
  if (scene == "split") return make_split(options);
  if (scene == "merge") return make_merge(frame, options);
  if (scene == "stream") return make_stream(options);
  if (scene == "stream-rock") return make_stream_rock(options);
  if (scene == "pour") return detail::make_pour_frame(frame, options);
  return detail::make_drop_frame(frame, options);
}

void write_frame_ply(const std::string& path, const FrameMesh& mesh, std::optional<double> fps) {
  if (mesh.velocities.size() != mesh.positions.size()) {
    throw InternalError(path + ": mesh has " + std::to_string(mesh.velocities.size()) + " velocities for " +
                        std::to_string(mesh.positions.size()) + " vertices");
  }
  std::vector<std::string> comments = {"fluidtex example scene"};
  if (fps) comments.push_back("fps=" + format_number(*fps));
  PlyWriter ply(comments, {{"x"}, {"y"}, {"z"}, {"vx"}, {"vy"}, {"vz"}}, mesh.positions.size(), mesh.triangles.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    for (int k = 0; k < 3; ++k) ply.put(mesh.positions[v][k]);
    for (int k = 0; k < 3; ++k) ply.put(mesh.velocities[v][k]);
  }
  for (const Tri& t : mesh.triangles) {
    ply.put_triangle(static_cast<std::uint32_t>(t[0]), static_cast<std::uint32_t>(t[1]),
                     static_cast<std::uint32_t>(t[2]));
  }
  ply.write(path);
}

std::string write_scene(const std::string& scene, const std::string& dir, const SceneOptions& options) {
  validate(scene, options);
  const std::filesystem::path folder(dir.empty() ? "." : dir);
  const std::string ext = "." + options.format;
  std::string pattern = (folder / (scene + ".####" + ext)).string();
  auto frame_path = [&](int frame) {
    char number[32];
    std::snprintf(number, sizeof(number), "%04d", frame);
    return (folder / (scene + "." + number + ext)).string();
  };
  // Frames are independent: generate and write them in parallel (the bytes
  // of each file do not depend on the schedule).
  tbb::parallel_for(1, options.frames + 1, [&](int frame) {
    const FrameMesh mesh = make_scene_frame(scene, frame, options);
    if (options.format == "vdb") {
      write_vdb_frame(frame_path(frame), mesh,
                      {.voxel_size = detail::volume_voxel_size(options), .staggered = options.staggered});
    } else {
      write_frame_ply(frame_path(frame), mesh, options.fps);
    }
  });
  return pattern;
}

}  // namespace fluidtex
