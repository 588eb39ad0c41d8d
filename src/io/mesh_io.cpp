// Reading one frame (see mesh_io.h).
//
// Parsing is OpenMesh 9's (PLYReader, OBJReader) into our own importer, which
// keeps the file's polygons verbatim. Around it, this file does what OpenMesh
// does not: it checks the PLY header first and hands OpenMesh a canonical
// copy of it, then validates what came back. Departures from plain
// `OpenMesh::IO::read_mesh`, and why:
//  - Own importer instead of a halfedge mesh: ImporterT drops faces with bad
//    or repeated indices without telling which, and splits non-manifold faces
//    onto fresh vertex copies that get no custom properties (their velocity
//    would read as 0). Our importer keeps the indices, so nothing is lost.
//  - Canonical header: OpenMesh reads x/y/z through a float Vec3f, accepts
//    only uchar/uint8/uint16/int list counts, and tokenises obj_info lines as
//    keywords. We rename positions and velocities to custom properties (which
//    it reads at their declared precision), map each list count type to the
//    supported type of the same size, and drop comments.
//  - Bodies are checked before parsing, up to the end of the faces, and
//    OpenMesh is given no more: binary bodies are measured (OpenMesh would
//    happily loop over a garbage list count), ASCII bodies are tokenised line
//    by line and every value checked against its type (OpenMesh's ASCII loop
//    checks only eof(), so a bad token or a short line would shift the data).
//  - PLYReader is a singleton with mutable per-file state and omerr is
//    process-wide, so the OpenMesh call is serialised and silenced.

#include "fluidtex/io/mesh_io.h"

#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/IO/reader/OBJReader.hh>
#include <OpenMesh/Core/IO/reader/PLYReader.hh>
#include <OpenMesh/Core/Mesh/ArrayKernel.hh>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <Eigen/Geometry>

#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/options.h"
#include "fluidtex/util/strings.h"
#include "openmesh_reader.h"
#include "ply_header.h"

namespace fluidtex {

namespace {

namespace OM = OpenMesh;
using namespace plyio;

// --- Importer -------------------------------------------------------------------------

/// Receives what an OpenMesh reader parses: vertex count (custom properties
/// land in `kernel`), points set through the standard path (OBJ), and the
/// polygons as flat index lists. Everything else the reader may offer
/// (normals, colours, texture coordinates) is ignored.
class FrameImporter final : public OM::IO::BaseImporter {
 public:
  OM::ArrayKernel kernel_;
  std::vector<Vec3> points_;
  std::vector<int> face_start_{0};
  std::vector<int> face_index_;

  OM::VertexHandle add_vertex(const OM::Vec3f& p) override {
    points_.emplace_back(p[0], p[1], p[2]);
    return kernel_.new_vertex();
  }
  OM::VertexHandle add_vertex(const OM::Vec3d& p) override {
    points_.emplace_back(p[0], p[1], p[2]);
    return kernel_.new_vertex();
  }
  OM::VertexHandle add_vertex() override {
    points_.emplace_back(0.0, 0.0, 0.0);
    return kernel_.new_vertex();
  }
  void set_point(OM::VertexHandle vh, const OM::Vec3f& p) override {
    if (vh.idx() >= 0 && static_cast<std::size_t>(vh.idx()) < points_.size())
      points_[vh.idx()] = Vec3(p[0], p[1], p[2]);
  }
  OM::FaceHandle add_face(const VHandles& indices) override {
    for (const OM::VertexHandle& h : indices) face_index_.push_back(h.idx());
    face_start_.push_back(static_cast<int>(face_index_.size()));
    return kernel_.new_face();
  }
  OM::BaseKernel* kernel() override { return &kernel_; }
  void reserve(unsigned nv, unsigned, unsigned nf) override {
    points_.reserve(nv);
    face_start_.reserve(nf + 1);
    face_index_.reserve(3u * nf);
  }
  std::size_t n_vertices() const override { return kernel_.n_vertices(); }
  std::size_t n_faces() const override { return kernel_.n_faces(); }
  std::size_t n_edges() const override { return 0; }

  // Unused attributes.
  OM::HalfedgeHandle add_edge(OM::VertexHandle, OM::VertexHandle) override { return OM::HalfedgeHandle(); }
  OM::FaceHandle add_face(OM::HalfedgeHandle) override { return OM::FaceHandle(); }
  void add_face_texcoords(OM::FaceHandle, OM::VertexHandle, const std::vector<OM::Vec2f>&) override {}
  void add_face_texcoords(OM::FaceHandle, OM::VertexHandle, const std::vector<OM::Vec3f>&) override {}
  void set_face_texindex(OM::FaceHandle, int) override {}
  void set_halfedge(OM::VertexHandle, OM::HalfedgeHandle) override {}
  void set_normal(OM::VertexHandle, const OM::Vec3f&) override {}
  void set_normal(OM::VertexHandle, const OM::Vec3d&) override {}
  void set_color(OM::VertexHandle, const OM::Vec3uc&) override {}
  void set_color(OM::VertexHandle, const OM::Vec4uc&) override {}
  void set_color(OM::VertexHandle, const OM::Vec3f&) override {}
  void set_color(OM::VertexHandle, const OM::Vec4f&) override {}
  void set_texcoord(OM::VertexHandle, const OM::Vec2f&) override {}
  void set_status(OM::VertexHandle, const OM::Attributes::StatusInfo&) override {}
  void set_next(OM::HalfedgeHandle, OM::HalfedgeHandle) override {}
  void set_face(OM::HalfedgeHandle, OM::FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(OM::HalfedgeHandle, const OM::Vec2f&) override {}
  void set_texcoord(OM::VertexHandle, const OM::Vec3f&) override {}
  void set_texcoord(OM::HalfedgeHandle, const OM::Vec3f&) override {}
  void set_status(OM::HalfedgeHandle, const OM::Attributes::StatusInfo&) override {}
  void set_color(OM::EdgeHandle, const OM::Vec3uc&) override {}
  void set_color(OM::EdgeHandle, const OM::Vec4uc&) override {}
  void set_color(OM::EdgeHandle, const OM::Vec3f&) override {}
  void set_color(OM::EdgeHandle, const OM::Vec4f&) override {}
  void set_status(OM::EdgeHandle, const OM::Attributes::StatusInfo&) override {}
  void set_normal(OM::FaceHandle, const OM::Vec3f&) override {}
  void set_normal(OM::FaceHandle, const OM::Vec3d&) override {}
  void set_color(OM::FaceHandle, const OM::Vec3uc&) override {}
  void set_color(OM::FaceHandle, const OM::Vec4uc&) override {}
  void set_color(OM::FaceHandle, const OM::Vec3f&) override {}
  void set_color(OM::FaceHandle, const OM::Vec4f&) override {}
  void set_status(OM::FaceHandle, const OM::Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}
};

// --- Values and polygons ----------------------------------------------------------------

/// Reads custom vertex property `name` (float or double, per `type`) into
/// component `axis` of `out`.
void take_property(OM::ArrayKernel& kernel, const std::string& name, PlyType type, int axis, std::vector<Vec3>& out) {
  auto copy = [&](auto handle) {
    if (!kernel.get_property_handle(handle, name))
      throw InternalError("OpenMesh did not create vertex property " + name);
    const auto& values = kernel.property(handle).data_vector();
    for (std::size_t i = 0; i < out.size() && i < values.size(); ++i) out[i][axis] = values[i];
  };
  if (type == PlyType::Float64) {
    copy(OM::VPropHandleT<double>());
  } else {
    copy(OM::VPropHandleT<float>());
  }
}

void check_finite(const std::string& path, const std::vector<Vec3>& values, const char* what) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (values[i].allFinite()) continue;
    const bool nan = values[i].array().isNaN().any();
    throw InputError(path, std::string(nan ? "NaN" : "Inf") + " in " + what + " of vertex " + std::to_string(i));
  }
}

/// Triangulates polygon `idx[0..n)` by ear clipping in the plane of its Newell
/// normal, so simple concave polygons give no inverted triangles; falls back
/// to a fan when the polygon is degenerate or self-intersecting.
void triangulate(const std::vector<Vec3>& pos, const int* idx, int n, std::vector<Tri>& out) {
  if (n == 3) {
    out.push_back({idx[0], idx[1], idx[2]});
    return;
  }
  Vec3 normal = Vec3::Zero();
  for (int i = 0; i < n; ++i) normal += pos[idx[i]].cross(pos[idx[(i + 1) % n]]);
  int drop = 0;
  normal.cwiseAbs().maxCoeff(&drop);
  const int u = (drop + 1) % 3, v = (drop + 2) % 3;
  const double sign = normal[drop] >= 0.0 ? 1.0 : -1.0;
  auto p2 = [&](int k) { return Vec2(pos[idx[k]][u], sign * pos[idx[k]][v]); };
  auto cross2 = [](const Vec2& a, const Vec2& b, const Vec2& c) {
    return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
  };
  std::vector<int> ring(n);
  for (int i = 0; i < n; ++i) ring[i] = i;
  const std::size_t first_out = out.size();
  while (ring.size() > 3 && normal.squaredNorm() > 0.0) {
    const int m = static_cast<int>(ring.size());
    bool clipped = false;
    for (int i = 0; i < m && !clipped; ++i) {
      const int a = ring[(i + m - 1) % m], b = ring[i], c = ring[(i + 1) % m];
      const Vec2 pa = p2(a), pb = p2(b), pc = p2(c);
      if (cross2(pa, pb, pc) <= 0.0) continue;  // reflex or flat corner
      bool empty = true;
      for (int k : ring) {
        if (k == a || k == b || k == c) continue;
        const Vec2 q = p2(k);
        if (cross2(pa, pb, q) > 0.0 && cross2(pb, pc, q) > 0.0 && cross2(pc, pa, q) > 0.0) {
          empty = false;
          break;
        }
      }
      if (!empty) continue;
      out.push_back({idx[a], idx[b], idx[c]});
      ring.erase(ring.begin() + i);
      clipped = true;
    }
    if (!clipped) break;
  }
  if (ring.size() == 3) {
    out.push_back({idx[ring[0]], idx[ring[1]], idx[ring[2]]});
    return;
  }
  out.resize(first_out);  // no valid ear: fall back to a fan
  for (int i = 1; i + 1 < n; ++i) out.push_back({idx[0], idx[i], idx[i + 1]});
}

/// Checks indices and turns the importer's polygons into triangles. Faces
/// with fewer than three corners are counted in `short_faces`.
std::vector<Tri> triangles_from(const std::string& path, const FrameImporter& im, const std::vector<Vec3>& pos,
                                std::size_t& short_faces) {
  std::vector<Tri> tris;
  tris.reserve(im.face_start_.size());
  const long long nv = static_cast<long long>(pos.size());
  for (std::size_t f = 0; f + 1 < im.face_start_.size(); ++f) {
    const int begin = im.face_start_[f], n = im.face_start_[f + 1] - begin;
    for (int k = 0; k < n; ++k) {
      const int i = im.face_index_[begin + k];
      if (i < 0 || i >= nv)
        throw InputError(path, "face " + std::to_string(f) + " has vertex index " + std::to_string(i) +
                                   " out of range (" + std::to_string(nv) + " vertices)");
    }
    if (n < 3) {
      ++short_faces;
      continue;
    }
    if (n > kMaxPolygonCorners) {
      throw InputError(path, "face " + std::to_string(f) + " has " + std::to_string(n) + " corners (at most " +
                                 std::to_string(kMaxPolygonCorners) + "; triangulate the mesh when exporting it)");
    }
    triangulate(pos, im.face_index_.data() + begin, n, tris);
  }
  return tris;
}

// --- Formats ------------------------------------------------------------------------------

FrameMesh read_ply(const std::string& path, const std::string& bytes, const ReadOptions& options,
                   std::size_t& short_faces) {
  const PlyHeader header = parse_ply_header(path, bytes);
  const PlyLayout layout = plan_ply_read(path, header, bytes, options.velocity_attr, options.require_velocities);

  FrameImporter im;
  std::string canonical = canonical_ply_header(header, layout);
  canonical.append(bytes, header.body_offset, layout.body_end - header.body_offset);
  std::istringstream in(std::move(canonical));
  const bool ok = run_openmesh_reader([&] {
    OM::IO::Options opt = OM::IO::Options::Custom;
    return OM::IO::PLYReader().read(in, im, opt);
  });
  const std::size_t nv = header.elements[layout.vertex_element].count;
  const std::size_t nf = header.elements[layout.face_element].count;
  // A short ASCII body leaves the stream failed (binary sizes were checked up
  // front, so failure there also means a short body).
  if (!ok || in.fail() || im.n_vertices() != nv || im.face_start_.size() != nf + 1) {
    const std::string what =
        header.format == PlyFormat::Ascii ? "truncated or unparsable ASCII body" : "truncated or malformed binary body";
    throw InputError(
        path, what + " (the header promises " + std::to_string(nv) + " vertices and " + std::to_string(nf) + " faces)");
  }

  FrameMesh mesh;
  mesh.positions.assign(nv, Vec3::Zero());
  mesh.velocities.assign(nv, Vec3::Zero());
  for (int a = 0; a < 3; ++a)
    take_property(im.kernel_, canonical_position_name(a), layout.position_type[a], a, mesh.positions);
  if (layout.has_velocity) {
    for (int a = 0; a < 3; ++a)
      take_property(im.kernel_, canonical_velocity_name(a), layout.velocity_type[a], a, mesh.velocities);
  }
  check_finite(path, mesh.positions, "position");
  check_finite(path, mesh.velocities, "velocity");
  mesh.triangles = triangles_from(path, im, mesh.positions, short_faces);
  return mesh;
}

/// Checks every vertex line ("v x y z [w]" or "v x y z r g b") of an OBJ:
/// OpenMesh's reader silently skips one it cannot parse, which shifts every
/// later index by one.
void check_obj_vertices(const std::string& path, const std::string& bytes) {
  std::size_t pos = 0;
  std::vector<std::string_view> tok;
  for (int line_no = 1; pos < bytes.size(); ++line_no) {
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    std::string_view line = std::string_view(bytes).substr(pos, eol - pos);
    pos = eol + 1;
    while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
    if (line.size() < 2 || line[0] != 'v' || (line[1] != ' ' && line[1] != '\t')) continue;
    split_tokens(line.substr(1), tok);
    auto where = [&] { return "line " + std::to_string(line_no) + " (vertex)"; };
    if (tok.size() != 3 && tok.size() != 4 && tok.size() != 6 && tok.size() != 7)
      throw InputError(path,
                       where() + ": " + std::to_string(tok.size()) + " values, expected x y z [w] or x y z r g b");
    for (std::string_view t : tok) ascii_value(path, t, PlyType::Float64, where);
  }
}

FrameMesh read_obj(const std::string& path, const std::string& bytes, const ReadOptions& options,
                   std::size_t& short_faces) {
  if (options.require_velocities)
    throw InputError(path,
                     "OBJ cannot carry velocities; use a PLY with per-vertex velocities or "
                     "--velocity-from-positions");
  if (bytes.substr(0, 4096).find('\0') != std::string::npos) throw InputError(path, "not an OBJ file (binary data)");
  check_obj_vertices(path, bytes);
  FrameImporter im;
  // OBJReader reads from the file itself (it resolves mtllib paths relative to it).
  const bool ok = run_openmesh_reader([&] {
    OM::IO::Options opt = OM::IO::Options::Default;
    return OM::IO::OBJReader().read(path, im, opt);
  });
  if (!ok) throw InputError(path, "malformed OBJ file");
  FrameMesh mesh;
  mesh.positions = im.points_;  // OpenMesh's OBJReader rounds positions to float
  mesh.velocities.assign(mesh.positions.size(), Vec3::Zero());
  check_finite(path, mesh.positions, "position");
  mesh.triangles = triangles_from(path, im, mesh.positions, short_faces);
  return mesh;
}

}  // namespace

CleanReport clean_frame(const std::string& path, FrameMesh& mesh, const CleanOptions& options) {
  const BBox box = bounding_box(mesh);
  const double diagonal = box.diagonal();
  CleanReport cleaned = clean_mesh(mesh, options);
  if (mesh.triangles.empty()) {
    if (!(diagonal > 0.0)) {
      throw InputError(path, "no surface: every vertex lies at one point (" + format_number(box.min.x()) + ", " +
                                 format_number(box.min.y()) + ", " + format_number(box.min.z()) + ")");
    }
    // Tolerances scale with the bounding box: one stray vertex far away
    // makes every real triangle "degenerate".
    throw InputError(path, "empty mesh: every face is degenerate at the scale of the bounding box (diagonal " +
                               format_number(diagonal) + "; a vertex far from the others?)");
  }
  return cleaned;
}

namespace {

/// InputError when the frame read has no vertices or no triangles, telling
/// a frame without liquid (nothing in it) from a damaged one: an OBJ whose
/// bytes hold no vertex line, faces that all have fewer than three corners.
void check_not_empty(const std::string& path, const std::string& ext, const FrameMesh& mesh, std::size_t short_faces) {
  if (mesh.positions.empty()) {
    if (ext == ".obj") {
      // OpenMesh reads what it can of a damaged OBJ and skips the rest.
      const std::string bytes = read_file_bytes(path);
      const bool text = std::all_of(bytes.begin(), bytes.end(), [](char c) {
        const auto u = static_cast<unsigned char>(c);
        return std::isprint(u) || std::isspace(u);
      });
      if (!text) throw InputError(path, "not a text OBJ (binary bytes, no vertex line): a damaged or misnamed file");
    }
    throw InputError(path, std::string("empty mesh (no vertices") + kNoLiquidHint + ")");
  }
  if (mesh.triangles.empty() && short_faces > 0) {
    throw InputError(path, "no triangles: all " + std::to_string(short_faces) +
                               " faces have fewer than three corners (a damaged file)");
  }
  if (mesh.triangles.empty()) throw InputError(path, std::string("empty mesh (no faces") + kNoLiquidHint + ")");
}

}  // namespace

std::optional<double> read_stated_fps(const std::string& path) {
  if (lower_extension(path) != ".ply") return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  std::string header;
  constexpr std::size_t kLongestHeader = 1 << 20;
  for (char chunk[4096]; header.find("end_header") == std::string::npos && header.size() < kLongestHeader;) {
    in.read(chunk, sizeof chunk);
    if (in.gcount() <= 0) break;
    header.append(chunk, static_cast<std::size_t>(in.gcount()));
  }
  try {
    return stated_fps(parse_ply_header(path, header).comments);
  } catch (const InputError&) {
    return std::nullopt;  // reading the frame reports what is wrong with it
  }
}

FrameMesh read_frame(const std::string& path, const ReadOptions& options, CleanReport* report) {
  require_regular_file(path, "mesh file");

  const std::string ext = lower_extension(path);
  if (ext != ".ply" && ext != ".obj" && ext != ".vdb")
    throw InputError(path, "unknown mesh format '" + ext + "' (expected .ply, .obj or .vdb)");
  std::error_code ec;
  if (std::filesystem::file_size(path, ec) == 0 && !ec) throw InputError(path, "empty file (0 bytes)");

  std::size_t short_faces = 0;
  FrameMesh mesh;
  if (ext == ".vdb") {
    mesh = read_vdb_frame(path, options.vdb, options.require_velocities);
  } else {
    const std::string bytes = read_file_bytes(path);
    mesh = ext == ".ply" ? read_ply(path, bytes, options, short_faces) : read_obj(path, bytes, options, short_faces);
  }
  check_not_empty(path, ext, mesh, short_faces);

  CleanReport cleaned;
  if (options.clean) {
    cleaned = clean_frame(path, mesh, options.clean_options);
  }
  cleaned.degenerate_faces += short_faces;  // polygons with < 3 corners never became triangles
  if (report) *report = cleaned;
  return mesh;
}

}  // namespace fluidtex
