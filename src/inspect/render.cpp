#include "fluidtex/inspect/render.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <numbers>

#include "fluidtex/util/error.h"

namespace fluidtex {

namespace {

/// Screen coordinates (u right, v up) and height towards the camera of p.
Vec3 axis_project(const Vec3& p, View view) {
  switch (view) {
    case View::Top: return {p.x(), p.y(), p.z()};
    case View::Front: return {p.x(), p.z(), -p.y()};
    case View::Side: return {p.y(), p.z(), p.x()};
  }
  return p;
}

Vec3 view_dir(View view) {  // towards the camera
  switch (view) {
    case View::Top: return {0, 0, 1};
    case View::Front: return {0, -1, 0};
    case View::Side: return {1, 0, 0};
  }
  return {0, 0, 1};
}

/// The atlas at uv (v up) as RGB (grey repeated).
void sample_uv(const TiledAtlas& atlas, const Vec2& uv, float out[3]) {
  float px[3] = {0, 0, 0};
  atlas.sample(uv, px, 3);
  for (int c = 0; c < 3; ++c) out[c] = px[std::min(c, atlas.first().channels - 1)];
}

constexpr float kBackground = 0.12f;

}  // namespace

Camera Camera::orthographic(View view, double min_u, double min_v, double max_u, double max_v, int width) {
  if (width < 1) throw InputError("", "--width must be at least 1");
  Camera c;
  c.view = view;
  c.width = width;
  c.min_u = min_u;
  c.max_v = max_v;
  c.scale = width / (max_u - min_u);
  c.height = std::max(1, static_cast<int>(std::lround((max_v - min_v) * c.scale)));
  return c;
}

Camera Camera::perspective_at(const Vec3& eye, const Vec3& target, double fov_deg, int width, int height) {
  if (width < 1 || height < 1) throw InputError("", "--width and --height must be at least 1");
  if (!(fov_deg > 0.0 && fov_deg < 180.0))
    throw InputError("", "--camera: the field of view must be in (0, 180) degrees");
  const Vec3 f = target - eye;
  if (!(f.norm() > 0.0) || !f.allFinite() || !eye.allFinite()) {
    throw InputError("", "--camera: the eye and the target must be distinct finite points");
  }
  Camera c;
  c.perspective = true;
  c.width = width, c.height = height;
  c.eye = eye, c.target = target, c.fov_deg = fov_deg;
  c.forward = f.normalized();
  // +z is up in the scenes; looking (nearly) along z, +y is.
  const Vec3 up0 = std::abs(c.forward.z()) > 0.99 ? Vec3::UnitY() : Vec3::UnitZ();
  c.right = c.forward.cross(up0).normalized();
  c.up = c.right.cross(c.forward);
  c.focal = 0.5 * height / std::tan(0.5 * fov_deg * std::numbers::pi / 180.0);
  c.near = 1e-6 * f.norm();
  return c;
}

Vec3 Camera::project(const Vec3& p) const {
  if (perspective) {
    const Vec3 d = p - eye;
    const double z = d.dot(forward);
    const double inv = z != 0.0 ? focal / z : 0.0;
    return {0.5 * width + d.dot(right) * inv, 0.5 * height - d.dot(up) * inv, z};
  }
  const Vec3 s = axis_project(p, view);
  return {(s.x() - min_u) * scale, (max_v - s.y()) * scale, -s.z()};
}

Vec3 Camera::toward_camera(const Vec3& p) const {
  if (!perspective) return view_dir(view);
  const Vec3 d = eye - p;
  const double n = d.norm();
  return n > 0 ? Vec3(d / n) : Vec3(-forward);
}

Vec2 Camera::image_displacement(const Vec3& p, const Vec3& d) const {
  const Vec3 a = project(p), b = project(p + d);
  return {b.x() - a.x(), b.y() - a.y()};
}

RenderOptions framed(const std::vector<Vec3>& positions, const RenderOptions& options) {
  RenderOptions out = options;
  if (options.perspective || (options.max_u > options.min_u && options.max_v > options.min_v)) return out;
  double lo_u = std::numeric_limits<double>::infinity(), lo_v = lo_u, hi_u = -lo_u, hi_v = -lo_u;
  for (const Vec3& p : positions) {
    const Vec3 s = axis_project(p, options.view);
    lo_u = std::min(lo_u, s.x()), hi_u = std::max(hi_u, s.x());
    lo_v = std::min(lo_v, s.y()), hi_v = std::max(hi_v, s.y());
  }
  if (!(hi_u >= lo_u)) return out;
  const double margin = 0.03 * std::max(hi_u - lo_u, hi_v - lo_v);
  out.min_u = lo_u - margin, out.max_u = hi_u + margin, out.min_v = lo_v - margin, out.max_v = hi_v + margin;
  return out;
}

Camera make_camera(const std::vector<Vec3>& positions, const RenderOptions& options) {
  if (options.perspective) {
    const int height = options.height > 0 ? options.height : std::max(1, options.width * 3 / 4);
    return Camera::perspective_at(options.eye, options.target, options.fov_deg, options.width, height);
  }
  const RenderOptions f = framed(positions, options);
  return Camera::orthographic(options.view, f.min_u, f.min_v, f.max_u, f.max_v, options.width);
}

GBuffer rasterize(const std::vector<Vec3>& positions, const std::vector<Tri>& triangles, const Camera& camera) {
  const int w = camera.width, h = camera.height;
  GBuffer g;
  g.width = w, g.height = h;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  g.face.assign(n, -1);
  g.bary.assign(n, Vec3::Zero());
  g.depth.assign(n, std::numeric_limits<double>::infinity());
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    Vec3 s[3];
    bool behind = false;
    for (int k = 0; k < 3; ++k) {
      s[k] = camera.project(positions[triangles[f][k]]);
      behind = behind || (camera.perspective && !(s[k].z() > camera.near));
    }
    if (behind) continue;
    const double area = (s[1].x() - s[0].x()) * (s[2].y() - s[0].y()) - (s[2].x() - s[0].x()) * (s[1].y() - s[0].y());
    if (!(std::abs(area) > 1e-12)) continue;
    const double fx0 = std::floor(std::min({s[0].x(), s[1].x(), s[2].x()}));
    const double fx1 = std::ceil(std::max({s[0].x(), s[1].x(), s[2].x()}));
    const double fy0 = std::floor(std::min({s[0].y(), s[1].y(), s[2].y()}));
    const double fy1 = std::ceil(std::max({s[0].y(), s[1].y(), s[2].y()}));
    if (!(fx1 >= 0 && fy1 >= 0 && fx0 <= w - 1 && fy0 <= h - 1)) continue;  // off screen (also NaN)
    const int x0 = std::max(0, static_cast<int>(fx0)), x1 = std::min(w - 1, static_cast<int>(fx1));
    const int y0 = std::max(0, static_cast<int>(fy0)), y1 = std::min(h - 1, static_cast<int>(fy1));
    const double inv_z[3] = {1.0 / s[0].z(), 1.0 / s[1].z(), 1.0 / s[2].z()};
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5, py = y + 0.5;
        const double l1 = ((px - s[0].x()) * (s[2].y() - s[0].y()) - (s[2].x() - s[0].x()) * (py - s[0].y())) / area;
        const double l2 = ((s[1].x() - s[0].x()) * (py - s[0].y()) - (px - s[0].x()) * (s[1].y() - s[0].y())) / area;
        const double l0 = 1.0 - l1 - l2;
        if (l0 < 0 || l1 < 0 || l2 < 0) continue;
        Vec3 b(l0, l1, l2);
        double z;
        if (camera.perspective) {
          // Screen-space weights → 3D barycentrics (1/z is affine on screen).
          const Vec3 q(l0 * inv_z[0], l1 * inv_z[1], l2 * inv_z[2]);
          const double sum = q.sum();
          z = 1.0 / sum;
          b = q / sum;
        } else {
          z = l0 * s[0].z() + l1 * s[1].z() + l2 * s[2].z();
        }
        const std::size_t i = texel_index(x, y, w);
        if (z >= g.depth[i]) continue;
        g.depth[i] = z;
        g.face[i] = static_cast<int>(f);
        g.bary[i] = b;
      }
    }
  }
  return g;
}

RenderResult render(const UVMesh& mesh, const Image& atlas, const RenderOptions& options) {
  return render(mesh, TiledAtlas::one(atlas), options);
}

RenderResult render(const UVMesh& mesh, const TiledAtlas& atlas, const RenderOptions& options) {
  RenderResult r;
  r.camera = make_camera(mesh.positions, options);
  r.gbuffer = rasterize(mesh.positions, mesh.triangles, r.camera);
  const Camera& camera = r.camera;
  const GBuffer& g = r.gbuffer;
  Image& out = r.color;
  out.width = g.width, out.height = g.height, out.channels = 3;
  out.pixels.assign(static_cast<std::size_t>(g.width) * g.height * 3, kBackground);
  const Vec3 towards = camera.perspective ? Vec3(-camera.forward) : view_dir(camera.view);
  const Vec3 light = (towards + Vec3(0.3, 0.4, 0.5)).normalized();
  for (std::size_t i = 0; i < g.face.size(); ++i) {
    const int f = g.face[i];
    if (f < 0) continue;
    const Vec3& l = g.bary[i];
    const Vec2 uv = interpolate(mesh.uvs, mesh.uv_triangles[f], l);
    float rgb[3];
    sample_uv(atlas, uv, rgb);
    double shade = 1.0;
    if (options.shade && !mesh.normals.empty()) {
      Vec3 n = interpolate(mesh.normals, mesh.triangles[f], l);
      if (n.norm() > 0) n.normalize();
      shade = 0.35 + 0.65 * std::abs(n.dot(light));
    }
    for (int c = 0; c < 3; ++c) out.pixels[i * 3 + c] = static_cast<float>(rgb[c] * shade);
  }
  return r;
}

Image render_textured(const UVMesh& mesh, const TiledAtlas& atlas, const RenderOptions& options) {
  return render(mesh, atlas, options).color;
}

Image render_textured(const UVMesh& mesh, const Image& atlas, const RenderOptions& options) {
  return render(mesh, atlas, options).color;
}

// --- Drawing --------------------------------------------------------------------

LinearRgb rgb_from_srgb8(const std::array<unsigned char, 3>& c) {
  LinearRgb out;
  for (int k = 0; k < 3; ++k) {
    const double v = c[k] / 255.0;
    out[k] = static_cast<float>(v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
  }
  return out;
}

namespace {

void put(Image& im, int x, int y, const LinearRgb& color) {
  if (x < 0 || y < 0 || x >= im.width || y >= im.height) return;
  for (int c = 0; c < std::min(3, im.channels); ++c) im.at(x, y, c) = color[c];
}

/// Pixel of a projected point (floor of its coordinates), clamped to a
/// range that cannot overflow int.
int pixel_of(double v) { return static_cast<int>(std::floor(std::clamp(v, -1e6, 1e6))); }

}  // namespace

void Canvas::plot(int x, int y, double depth, const LinearRgb& color) {
  if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
  if (depth_test && !gbuffer.visible(x, y, depth, depth_bias)) return;
  put(image, x, y, color);
}

void Canvas::line(const Vec3& a, const Vec3& b, const LinearRgb& color) {
  if (!camera.in_front(a) || !camera.in_front(b)) return;
  const Vec3 pa = camera.project(a), pb = camera.project(b);
  const double length = std::max(std::abs(pb.x() - pa.x()), std::abs(pb.y() - pa.y()));
  if (!std::isfinite(length)) return;
  // Sampled in 3D so that the depth is right under perspective too.
  const int n = static_cast<int>(std::min(std::ceil(length), 4.0 * (image.width + image.height))) + 1;
  for (int k = 0; k <= n; ++k) {
    const Vec3 q = camera.project(a + (b - a) * (static_cast<double>(k) / n));
    plot(pixel_of(q.x()), pixel_of(q.y()), q.z(), color);
  }
}

void Canvas::disc(const Vec3& p, double radius, const LinearRgb& color) {
  if (!camera.in_front(p)) return;
  const Vec3 c = camera.project(p);
  const int cx = pixel_of(c.x()), cy = pixel_of(c.y());
  if (cx < 0 || cy < 0 || cx >= image.width || cy >= image.height) return;
  if (depth_test && !gbuffer.visible(cx, cy, c.z(), depth_bias)) return;
  const LinearRgb rim = {0.01f, 0.01f, 0.01f};
  const int r = static_cast<int>(std::ceil(radius));
  for (int y = cy - r; y <= cy + r; ++y) {
    for (int x = cx - r; x <= cx + r; ++x) {
      const double d = std::hypot(x + 0.5 - c.x(), y + 0.5 - c.y());
      if (d <= radius - 1.0)
        put(image, x, y, color);
      else if (d <= radius)
        put(image, x, y, rim);
    }
  }
}

void Canvas::arrow(const Vec3& p, const Vec3& d, const LinearRgb& color) {
  if (!camera.in_front(p) || !camera.in_front(p + d)) return;
  const Vec3 a = camera.project(p), b = camera.project(p + d);
  const int ax = pixel_of(a.x()), ay = pixel_of(a.y());
  if (ax < 0 || ay < 0 || ax >= image.width || ay >= image.height) return;
  if (depth_test && !gbuffer.visible(ax, ay, a.z(), depth_bias)) return;
  const Vec2 s(b.x() - a.x(), b.y() - a.y());
  const double length = s.norm();
  auto segment = [&](const Vec2& from, const Vec2& to) {
    const double n = std::ceil(std::min(std::max(std::abs(to.x() - from.x()), std::abs(to.y() - from.y())),
                                        4.0 * (image.width + image.height)));
    for (int k = 0; k <= static_cast<int>(n); ++k) {
      const Vec2 q = from + (to - from) * (n > 0 ? k / n : 0.0);
      put(image, pixel_of(q.x()), pixel_of(q.y()), color);
    }
  };
  const Vec2 from(a.x(), a.y()), tip(b.x(), b.y());
  put(image, ax, ay, color);
  if (!(length >= 1.0) || !std::isfinite(length)) return;
  segment(from, tip);
  const Vec2 back = -s / length;
  const double head = std::min(6.0, 0.35 * length);
  const double cs = std::cos(0.45), sn = std::sin(0.45);
  segment(tip, tip + head * Vec2(cs * back.x() - sn * back.y(), sn * back.x() + cs * back.y()));
  segment(tip, tip + head * Vec2(cs * back.x() + sn * back.y(), -sn * back.x() + cs * back.y()));
}

// --- Contact sheet -----------------------------------------------------------------

namespace {

/// 3×5 glyphs for 0-9 and '-', one row per 3 bits (MSB left).
const std::array<std::array<unsigned char, 5>, 11> kGlyphs = {{
    {7, 5, 5, 5, 7},
    {2, 6, 2, 2, 7},
    {7, 1, 7, 4, 7},
    {7, 1, 7, 1, 7},
    {5, 5, 7, 1, 1},
    {7, 4, 7, 1, 7},
    {7, 4, 7, 5, 7},
    {7, 1, 1, 1, 1},
    {7, 5, 7, 5, 7},
    {7, 5, 7, 1, 7},
    {0, 0, 7, 0, 0},
}};

void draw_label(Image& im, int x0, int y0, const std::string& text, int scale) {
  int glyphs = 0;
  for (char ch : text) glyphs += (std::isdigit(static_cast<unsigned char>(ch)) || ch == '-') ? 1 : 0;
  if (glyphs == 0) return;
  const int w = (glyphs * 4 + 1) * scale, h = 7 * scale;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) put(im, x0 + x, y0 + y, {0.0f, 0.0f, 0.0f});
  }
  int gx = x0 + scale;
  for (char ch : text) {
    int g = ch == '-' ? 10 : std::isdigit(static_cast<unsigned char>(ch)) ? ch - '0' : -1;
    if (g < 0) continue;
    for (int row = 0; row < 5; ++row) {
      for (int col = 0; col < 3; ++col) {
        if (!((kGlyphs[g][row] >> (2 - col)) & 1)) continue;
        for (int sy = 0; sy < scale; ++sy) {
          for (int sx = 0; sx < scale; ++sx)
            put(im, gx + col * scale + sx, y0 + (row + 1) * scale + sy, {1.0f, 1.0f, 1.0f});
        }
      }
    }
    gx += 4 * scale;
  }
}

}  // namespace

Image contact_sheet(const std::vector<Image>& images, const std::vector<std::string>& labels, int gap) {
  Image sheet;
  if (images.empty()) return sheet;
  int cw = 0, ch = 0;
  for (const Image& im : images) cw = std::max(cw, im.width), ch = std::max(ch, im.height);
  const int n = static_cast<int>(images.size());
  int cols = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
  while (cols * cols < n) ++cols;
  while ((cols - 1) * (cols - 1) >= n) --cols;
  const int rows = (n + cols - 1) / cols;
  sheet.width = cols * cw + (cols + 1) * gap;
  sheet.height = rows * ch + (rows + 1) * gap;
  sheet.channels = 3;
  sheet.pixels.assign(static_cast<std::size_t>(sheet.width) * sheet.height * 3, 0.03f);
  const int scale = std::max(1, cw / 192);
  for (int k = 0; k < n; ++k) {
    const Image& im = images[k];
    const int ox = gap + (k % cols) * (cw + gap), oy = gap + (k / cols) * (ch + gap);
    for (int y = 0; y < im.height; ++y) {
      for (int x = 0; x < im.width; ++x) {
        for (int c = 0; c < 3; ++c) sheet.at(ox + x, oy + y, c) = im.at(x, y, std::min(c, im.channels - 1));
      }
    }
    if (static_cast<std::size_t>(k) < labels.size()) draw_label(sheet, ox + scale, oy + scale, labels[k], scale);
  }
  return sheet;
}

}  // namespace fluidtex
