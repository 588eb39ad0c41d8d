#include "fluidtex/inspect/motion_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <OpenImageIO/color.h>
#include <oneapi/tbb/parallel_for.h>
#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>

#include "fluidtex/geometry/surface.h"
#include "fluidtex/util/check.h"
#include "fluidtex/util/random.h"

namespace fluidtex {

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
  const int nc = std::min(at_t.atlas.first().channels, at_next.atlas.first().channels);
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
        const double l = luminance_at<double>(im, texel_index(x, y, im.width));
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

FlowError flow_against_velocity(const FrameMesh& mesh, const TexturedFrame& at_t, const TexturedFrame& at_next,
                                const LiquidMotion& motion, const RenderOptions& view, double max_motion) {
  std::vector<Vec3> both = at_t.mesh.positions;
  both.insert(both.end(), at_next.mesh.positions.begin(), at_next.mesh.positions.end());
  RenderOptions o = view;
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
  return optical_flow_error(a.color, b.color, expected, mask, max_motion);
}

}  // namespace fluidtex
