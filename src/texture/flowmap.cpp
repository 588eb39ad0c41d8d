// Two-phase advected UVs, the flow-map baseline (see flowmap.h).
#include "fluidtex/texture/flowmap.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include "fluidtex/util/check.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/random.h"
#include "fluidtex/util/timing.h"

namespace fluidtex {

void FlowMapOptions::validate() const { check_options(*this); }

std::array<int, 2> phase_ages(int step, int period) {
  const int half = period / 2;
  return {((step % period) + period) % period, (((step - half) % period) + period) % period};
}

std::array<double, 2> phase_weights(int step, int period) {
  const std::array<int, 2> age = phase_ages(step, period);
  std::array<double, 2> w;
  for (int k = 0; k < 2; ++k) {
    const double s = std::sin(std::numbers::pi * static_cast<double>(age[k]) / period);
    w[k] = s * s;
  }
  // Never both 0: the phases reset half a period apart (N >= 2).
  const double sum = w[0] + w[1];
  return {w[0] / sum, w[1] / sum};
}

Vec2 rest_uv(const Vec3& p, Axis axis, double tile_size) {
  switch (axis) {
    case Axis::X: return Vec2(p.y(), p.z()) / tile_size;
    case Axis::Y: return Vec2(p.z(), p.x()) / tile_size;
    case Axis::Z: break;
  }
  return Vec2(p.x(), p.y()) / tile_size;
}

namespace {

/// The two uvs of a vertex at `x` moving at `vel`: traced back over dt onto
/// the `previous` surface (semi-Lagrangian) and read from its uv sets `uv`
/// (none on the first frame and when both phases reset), or its rest uvs for a phase that resets (or a trace that
/// finds no surface).
std::array<Vec2, 2> advected_uvs(const Vec3& x, const Vec3& vel, double dt, const SurfaceIndex* previous,
                                 const std::array<std::vector<Vec2>, 2>& uv, const std::array<bool, 2>& reset,
                                 Axis axis, double tile) {
  const Vec2 rest = rest_uv(x, axis, tile);
  SurfacePoint s;
  Vec2 inflow = Vec2::Zero();
  if (previous) {
    const Vec3 from = x - dt * vel;
    s = previous->closest_point(from);
    // Traced back beyond the rim of an open surface (inflow): the uv field
    // is extended past the rim with the rest gradient, so the texture
    // keeps flowing in instead of streaking from the rim's values.
    if (s.valid() && previous->on_boundary(s)) inflow = rest_uv(from, axis, tile) - rest_uv(s.position, axis, tile);
  }
  std::array<Vec2, 2> out;
  for (int k = 0; k < 2; ++k) {
    if (reset[k] || !s.valid()) {
      out[k] = rest;
      continue;
    }
    const Tri& t = previous->mesh().triangles[s.face];
    out[k] = interpolate(uv[k], t, s.bary) + inflow;
  }
  return out;
}

}  // namespace

FlowMapAdvector::FlowMapAdvector(FlowMapSettings settings) : settings_(std::move(settings)) {
  settings_.flowmap.validate();
}

FlowMapStep FlowMapAdvector::step(std::shared_ptr<const FrameMesh> mesh, double dt) {
  FlowMapStep report;
  report.step = steps_;
  auto t0 = Clock::now();
  // The index refers to *mesh; the deleter keeps the mesh alive with it.
  std::shared_ptr<const SurfaceIndex> surface(new SurfaceIndex(*mesh), [mesh](const SurfaceIndex* s) { delete s; });
  if (steps_ == 0) {
    settings_.tracking = settings_.tracking.resolved(bounding_box(*mesh).diagonal());
    tile_size_ = settings_.tracking.exemplar_tile_size(settings_.exemplar_size);
    if (!(tile_size_ > 0.0) || !std::isfinite(tile_size_)) {
      throw InputError("", "flowmap: the first frame is degenerate (zero bounding box): no texture scale");
    }
  }
  report.seconds.emplace_back("surface", seconds_since(t0));

  t0 = Clock::now();
  const int period = settings_.flowmap.period;
  const std::array<int, 2> age = phase_ages(steps_, period);
  for (int k = 0; k < 2; ++k) report.reset[k] = steps_ == 0 || age[k] == 0;
  const std::size_t nv = mesh->num_vertices();
  std::array<std::vector<Vec2>, 2> next;
  for (auto& uv : next) uv.resize(nv);
  const Axis axis = settings_.flowmap.axis;
  const double tile = tile_size_;
  const bool advect = steps_ > 0 && !(report.reset[0] && report.reset[1]);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t v = r.begin(); v != r.end(); ++v) {
      const Vec3 vel = v < mesh->velocities.size() ? mesh->velocities[v] : Vec3::Zero();
      const std::array<Vec2, 2> uv =
          advected_uvs(mesh->positions[v], vel, dt, advect ? surface_.get() : nullptr, uv_, report.reset, axis, tile);
      next[0][v] = uv[0], next[1][v] = uv[1];
    }
  });
  uv_ = std::move(next);
  if (steps_ > 0) {
    for (int k = 0; k < 2; ++k) cycle_[k] += report.reset[k];
  }
  report.seconds.emplace_back("advect", seconds_since(t0));
  mesh_ = std::move(mesh);
  surface_ = std::move(surface);
  ++steps_;
  return report;
}

FlowMapFrame FlowMapAdvector::frame() const {
  FlowMapFrame f;
  f.uv = uv_;
  f.weight = phase_weights(steps_ > 0 ? steps_ - 1 : 0, settings_.flowmap.period);
  for (int k = 0; k < 2; ++k) {
    const auto phase = static_cast<std::uint64_t>(k), cycle = static_cast<std::uint64_t>(cycle_[k]);
    f.anchor[k] = Vec2(uniform(settings_.seed, Stream::FlowMapAnchor, phase, cycle, 0),
                       uniform(settings_.seed, Stream::FlowMapAnchor, phase, cycle, 1));
  }
  f.uv_scale = settings_.tracking.uv_scale;
  return f;
}

SynthesisResult synthesize_flowmap(const SurfaceIndex& surface, const Atlas& atlas, const TexelMap& map,
                                   const FlowMapFrame& frame, const Exemplar& exemplar, Blend blend, bool aov) {
  const int n = atlas.size;
  const std::size_t texel_count = static_cast<std::size_t>(n) * n;
  const int nc = exemplar.channels();
  const FrameMesh& mesh = surface.mesh();
  for (const auto& uv : frame.uv) {
    FLUIDTEX_CHECK_EQ(uv.size(), mesh.num_vertices());
  }
  SynthesisResult result = SynthesisResult::blank(n, nc, aov);
  const Blender blender(exemplar, blend);
  const double w0 = frame.weight[0], w1 = frame.weight[1];
  const double sum_w = w0 + w1, sum_w2 = w0 * w0 + w1 * w1;
  const int dominant = w0 >= w1 ? 0 : 1;
  const auto dominant_rgb = id_color(static_cast<std::uint32_t>(dominant));
  std::vector<char> mask(texel_count, 0);
  // Rows in parallel: every texel depends only on its own face and
  // barycentrics, so the result does not depend on the split.
  struct Tally {
    std::size_t chart = 0, clamped = 0;
  };
  std::vector<Tally> tally(static_cast<std::size_t>(n));
  tbb::parallel_for(0, n, [&](int y) {
    Tally& t = tally[static_cast<std::size_t>(y)];
    for (int x = 0; x < n; ++x) {
      const std::size_t i = texel_index(x, y, n);
      const int f = map.face[i];
      if (f < 0) continue;
      ++t.chart;
      mask[i] = 1;
      const Tri& tri = mesh.triangles[f];
      const Vec3 l = map.bary(i);
      double sum[3] = {0, 0, 0};
      for (int k = 0; k < 2; ++k) {
        const double w = frame.weight[k];
        if (!(w > 0.0)) continue;
        const std::vector<Vec2>& uv = frame.uv[k];
        const Vec2 u = frame.anchor[k] + frame.uv_scale * interpolate(uv, tri, l);
        double term[3];
        blender.sample(u.x(), u.y(), term);
        for (int c = 0; c < nc; ++c) sum[c] += w * term[c];
      }
      t.clamped += blender.resolve(sum, sum_w, sum_w2, result.color.pixel(i));
      if (aov) {
        result.weight.pixels[i] = static_cast<float>(sum_w);
        result.count.pixels[i] = static_cast<float>((w0 > 0.0) + (w1 > 0.0));
        for (int c = 0; c < 3; ++c) result.patch.pixel(i)[c] = dominant_rgb[c] / 255.0f;
      }
    }
  });
  for (const Tally& t : tally) {
    result.chart_texels += t.chart;
    result.clamped_texels += t.clamped;
  }
  dilate(result.color, mask, 8);
  return result;
}

}  // namespace fluidtex
