#include "fluidtex/render.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include "fluidtex/error.h"

namespace fluidtex {

View view_from_string(const std::string& s) {
  if (s == "top") return View::Top;
  if (s == "front") return View::Front;
  if (s == "side") return View::Side;
  throw InputError("", "--view must be top, front or side (got '" + s + "')");
}

namespace {

/// Screen coordinates (u right, v up) and depth (larger = nearer) of p.
Vec3 project(const Vec3& p, View view) {
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

void sample_bilinear(const Image& im, double u, double v, float out[3]) {
  const double x = std::clamp(u, 0.0, 1.0) * im.width - 0.5, y = (1.0 - std::clamp(v, 0.0, 1.0)) * im.height - 0.5;
  const int x0 = std::clamp(static_cast<int>(std::floor(x)), 0, im.width - 1);
  const int y0 = std::clamp(static_cast<int>(std::floor(y)), 0, im.height - 1);
  const int x1 = std::min(x0 + 1, im.width - 1), y1 = std::min(y0 + 1, im.height - 1);
  const double tx = std::clamp(x - x0, 0.0, 1.0), ty = std::clamp(y - y0, 0.0, 1.0);
  for (int c = 0; c < 3; ++c) {
    const int ch = std::min(c, im.channels - 1);
    const double a = im.at(x0, y0, ch) * (1 - tx) + im.at(x1, y0, ch) * tx;
    const double b = im.at(x0, y1, ch) * (1 - tx) + im.at(x1, y1, ch) * tx;
    out[c] = static_cast<float>(a * (1 - ty) + b * ty);
  }
}

}  // namespace

Image render_textured(const UVMesh& mesh, const Image& atlas, const RenderOptions& options) {
  double lo_u = options.min_u, lo_v = options.min_v, hi_u = options.max_u, hi_v = options.max_v;
  if (!(hi_u > lo_u) || !(hi_v > lo_v)) {
    lo_u = lo_v = std::numeric_limits<double>::infinity();
    hi_u = hi_v = -lo_u;
    for (const Vec3& p : mesh.positions) {
      const Vec3 s = project(p, options.view);
      lo_u = std::min(lo_u, s.x()), hi_u = std::max(hi_u, s.x());
      lo_v = std::min(lo_v, s.y()), hi_v = std::max(hi_v, s.y());
    }
    const double margin = 0.03 * std::max(hi_u - lo_u, hi_v - lo_v);
    lo_u -= margin, hi_u += margin, lo_v -= margin, hi_v += margin;
  }
  const int w = options.width;
  const double scale = w / (hi_u - lo_u);
  const int h = std::max(1, static_cast<int>(std::lround((hi_v - lo_v) * scale)));
  Image out;
  out.width = w, out.height = h, out.channels = 3;
  out.pixels.assign(static_cast<std::size_t>(w) * h * 3, 0.12f);
  std::vector<double> depth(static_cast<std::size_t>(w) * h, -std::numeric_limits<double>::infinity());
  const Vec3 light = (view_dir(options.view) + Vec3(0.3, 0.4, 0.5)).normalized();
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    Vec3 s[3];
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = project(mesh.positions[mesh.triangles[f][k]], options.view);
      s[k] = Vec3((p.x() - lo_u) * scale, (hi_v - p.y()) * scale, p.z());
    }
    const double area = (s[1].x() - s[0].x()) * (s[2].y() - s[0].y()) - (s[2].x() - s[0].x()) * (s[1].y() - s[0].y());
    if (!(std::abs(area) > 1e-12)) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({s[0].x(), s[1].x(), s[2].x()}))));
    const int x1 = std::min(w - 1, static_cast<int>(std::ceil(std::max({s[0].x(), s[1].x(), s[2].x()}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({s[0].y(), s[1].y(), s[2].y()}))));
    const int y1 = std::min(h - 1, static_cast<int>(std::ceil(std::max({s[0].y(), s[1].y(), s[2].y()}))));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5, py = y + 0.5;
        const double l1 = ((px - s[0].x()) * (s[2].y() - s[0].y()) - (s[2].x() - s[0].x()) * (py - s[0].y())) / area;
        const double l2 = ((s[1].x() - s[0].x()) * (py - s[0].y()) - (px - s[0].x()) * (s[1].y() - s[0].y())) / area;
        const double l0 = 1.0 - l1 - l2;
        if (l0 < 0 || l1 < 0 || l2 < 0) continue;
        const double z = l0 * s[0].z() + l1 * s[1].z() + l2 * s[2].z();
        const std::size_t i = static_cast<std::size_t>(y) * w + x;
        if (z <= depth[i]) continue;
        depth[i] = z;
        const Tri& ut = mesh.uv_triangles[f];
        const Vec2 uv = l0 * mesh.uvs[ut[0]] + l1 * mesh.uvs[ut[1]] + l2 * mesh.uvs[ut[2]];
        float rgb[3];
        sample_bilinear(atlas, uv.x(), uv.y(), rgb);
        double shade = 1.0;
        if (options.shade && !mesh.normals.empty()) {
          const Tri& t = mesh.triangles[f];
          Vec3 n = l0 * mesh.normals[t[0]] + l1 * mesh.normals[t[1]] + l2 * mesh.normals[t[2]];
          if (n.norm() > 0) n.normalize();
          shade = 0.35 + 0.65 * std::abs(n.dot(light));
        }
        for (int c = 0; c < 3; ++c) out.pixels[i * 3 + c] = static_cast<float>(rgb[c] * shade);
      }
    }
  }
  return out;
}

UVMesh read_uv_mesh_obj(const std::string& path) {
  using Mesh = OpenMesh::PolyMesh_ArrayKernelT<>;
  Mesh m;
  m.request_halfedge_texcoords2D();
  m.request_vertex_normals();
  OpenMesh::IO::Options opt = OpenMesh::IO::Options::FaceTexCoord | OpenMesh::IO::Options::VertexNormal;
  if (!OpenMesh::IO::read_mesh(m, path, opt)) throw InputError(path, "cannot read UV mesh (OBJ)");
  if (!opt.check(OpenMesh::IO::Options::FaceTexCoord)) throw InputError(path, "UV mesh has no texture coordinates");
  UVMesh out;
  for (auto v : m.vertices()) {
    const auto p = m.point(v);
    out.positions.emplace_back(p[0], p[1], p[2]);
    const auto n = m.normal(v);
    out.normals.emplace_back(n[0], n[1], n[2]);
  }
  for (auto f : m.faces()) {
    std::vector<int> vs, uvs;
    for (auto h : m.fh_range(f)) {
      vs.push_back(m.to_vertex_handle(h).idx());
      const auto t = m.texcoord2D(h);
      uvs.push_back(static_cast<int>(out.uvs.size()));
      out.uvs.emplace_back(t[0], t[1]);
    }
    for (std::size_t k = 1; k + 1 < vs.size(); ++k) {
      out.triangles.push_back({vs[0], vs[k], vs[k + 1]});
      out.uv_triangles.push_back({uvs[0], uvs[k], uvs[k + 1]});
    }
  }
  return out;
}

}  // namespace fluidtex
