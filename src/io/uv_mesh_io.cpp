// UV mesh writers and readers (see uv_mesh_io.h).
//
// The writers are written by hand rather than through OpenMesh::IO: OpenMesh's halfedge
// structure cannot hold non-manifold frames (it drops or duplicates faces
// around complex edges/vertices), and fluid surfaces must be passed through
// unchanged, vertex for vertex and face for face.
//
// Numbers are written as 32-bit floats (what the PLY holds and what DCC tools
// read) in the shortest text that round-trips (std::to_chars: exact and
// locale-independent), so the same mesh always gives the same bytes.
#include "fluidtex/io/uv_mesh_io.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <utility>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include "fluidtex/io/mesh_io.h"
#include "fluidtex/io/ply_writer.h"
#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/strings.h"
#include "openmesh_reader.h"
#include "ply_header.h"

namespace fluidtex {

namespace fs = std::filesystem;

namespace {

constexpr const char* kMaterialName = "fluidtex_atlas";

/// Checks the mesh's arrays against each other; a mismatch is a bug upstream.
void validate(const std::string& path, const UVMesh& mesh) {
  auto fail = [&](const std::string& what) { throw InternalError(path + ": " + what); };
  const auto nv = static_cast<long long>(mesh.positions.size());
  const auto nuv = static_cast<long long>(mesh.uvs.size());
  if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
    fail("UV mesh has " + std::to_string(mesh.normals.size()) + " normals for " + std::to_string(nv) + " vertices");
  if (!mesh.velocities.empty() && mesh.velocities.size() != mesh.positions.size())
    fail("UV mesh has " + std::to_string(mesh.velocities.size()) + " velocities for " + std::to_string(nv) +
         " vertices");
  if (!mesh.uv_triangles.empty() && mesh.uv_triangles.size() != mesh.triangles.size())
    fail("UV mesh has " + std::to_string(mesh.uv_triangles.size()) + " uv triangles for " +
         std::to_string(mesh.triangles.size()) + " triangles");
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (mesh.triangles[f][k] < 0 || mesh.triangles[f][k] >= nv)
        fail("UV mesh triangle " + std::to_string(f) + " has vertex index out of range");
      if (!mesh.uv_triangles.empty() && (mesh.uv_triangles[f][k] < 0 || mesh.uv_triangles[f][k] >= nuv))
        fail("UV mesh triangle " + std::to_string(f) + " has uv index out of range");
    }
  }
  for (const Vec3& p : mesh.positions)
    if (!p.allFinite()) fail("UV mesh has a non-finite position");
  for (const Vec3& n : mesh.normals)
    if (!n.allFinite()) fail("UV mesh has a non-finite normal");
  for (const Vec2& t : mesh.uvs)
    if (!t.allFinite()) fail("UV mesh has a non-finite uv");
}

void append_float(std::string& out, double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, static_cast<float>(v));
  out.append(buf, r.ptr);
}

void append_int(std::string& out, long long v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

/// The map_Kd reference: as given when relative (taken relative to the OBJ's
/// folder); an absolute path is made relative to the OBJ's folder.
std::string texture_reference(const fs::path& obj_path, const std::string& image) {
  fs::path img(image);
  if (img.is_absolute()) {
    const fs::path dir = fs::absolute(obj_path).parent_path();
    const fs::path rel = img.lexically_relative(dir);
    if (!rel.empty()) img = rel;
  }
  return img.generic_string();
}

std::string mtl_text(const fs::path& obj_path, const MaterialMaps& maps) {
  std::string t = "# fluidtex atlas material\n";
  t += "newmtl ";
  t += kMaterialName;
  t += "\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nd 1\nillum 1\nmap_Kd ";
  t += texture_reference(obj_path, maps.color);
  t += '\n';
  if (!maps.displacement.empty()) {
    const std::string height = texture_reference(obj_path, maps.displacement);
    char multiplier[64];
    std::snprintf(multiplier, sizeof multiplier, "%.9g", maps.bump_height);
    t += "disp " + height + "\nbump -bm " + multiplier + " " + height + "\n";
  }
  if (!maps.normal.empty()) t += "norm " + texture_reference(obj_path, maps.normal) + "\n";
  return t;
}

std::string obj_text(const UVMesh& mesh, const std::string& mtl_file) {
  std::string t;
  t.reserve(mesh.positions.size() * 64 + mesh.triangles.size() * 40);
  t += "# fluidtex UV mesh\n";
  if (!mtl_file.empty()) {
    t += "mtllib ";
    t += mtl_file;
    t += '\n';
  }
  for (const Vec3& p : mesh.positions) {
    t += "v ";
    append_float(t, p.x());
    t += ' ';
    append_float(t, p.y());
    t += ' ';
    append_float(t, p.z());
    t += '\n';
  }
  for (const Vec2& uv : mesh.uvs) {
    t += "vt ";
    append_float(t, uv.x());
    t += ' ';
    append_float(t, uv.y());
    t += '\n';
  }
  for (const Vec3& n : mesh.normals) {
    t += "vn ";
    append_float(t, n.x());
    t += ' ';
    append_float(t, n.y());
    t += ' ';
    append_float(t, n.z());
    t += '\n';
  }
  if (!mtl_file.empty()) {
    t += "usemtl ";
    t += kMaterialName;
    t += '\n';
  }
  const bool has_uv = !mesh.uv_triangles.empty();
  const bool has_n = !mesh.normals.empty();
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    t += 'f';
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles[f][k] + 1;
      t += ' ';
      append_int(t, v);
      if (has_uv || has_n) {
        t += '/';
        if (has_uv) append_int(t, mesh.uv_triangles[f][k] + 1);
        if (has_n) {
          t += '/';
          append_int(t, v);  // normals are per vertex: same index
        }
      }
    }
    t += '\n';
  }
  return t;
}

PlyWriter ply_writer(const UVMesh& mesh) {
  // One output vertex per distinct (vertex, uv index) pair used by a corner,
  // sorted by vertex then uv index; vertices no triangle uses are kept with
  // uv (0, 0) (uv index -1) so the positions pass through unchanged.
  const bool has_uv = !mesh.uv_triangles.empty();
  std::vector<std::pair<int, int>> keys;
  keys.reserve(mesh.positions.size() + mesh.triangles.size());
  std::vector<char> used(mesh.positions.size(), 0);
  for (size_t f = 0; f < mesh.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles[f][k];
      used[v] = 1;
      keys.emplace_back(v, has_uv ? mesh.uv_triangles[f][k] : -1);
    }
  for (size_t v = 0; v < used.size(); ++v)
    if (!used[v]) keys.emplace_back(static_cast<int>(v), -1);
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  auto index_of = [&](int v, int uv) {
    return static_cast<std::uint32_t>(std::lower_bound(keys.begin(), keys.end(), std::make_pair(v, uv)) - keys.begin());
  };

  const bool has_velocity = !mesh.velocities.empty();
  std::vector<PlyWriter::Property> properties;
  for (const char* p : {"x", "y", "z", "nx", "ny", "nz", "u", "v"}) properties.push_back({p});
  if (has_velocity) {
    for (const char* p : {"vx", "vy", "vz"}) properties.push_back({p});
  }
  PlyWriter ply({"fluidtex UV mesh"}, properties, keys.size(), mesh.triangles.size());
  for (const auto& [v, uvi] : keys) {
    const Vec3& p = mesh.positions[v];
    const Vec3 n = mesh.normals.empty() ? Vec3::Zero().eval() : mesh.normals[v];
    const Vec2 uv = uvi >= 0 ? mesh.uvs[uvi] : Vec2::Zero().eval();
    for (int i = 0; i < 3; ++i) ply.put(p[i]);
    for (int i = 0; i < 3; ++i) ply.put(n[i]);
    ply.put(uv.x());
    ply.put(uv.y());
    if (has_velocity) {
      for (int i = 0; i < 3; ++i) ply.put(mesh.velocities[v][i]);
    }
  }
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto corner = [&](int k) { return index_of(mesh.triangles[f][k], has_uv ? mesh.uv_triangles[f][k] : -1); };
    ply.put_triangle(corner(0), corner(1), corner(2));
  }
  return ply;
}

}  // namespace

void write_uv_mesh_obj(const std::string& path, const UVMesh& mesh, const MaterialMaps& maps) {
  validate(path, mesh);
  std::string mtl_file;
  if (!maps.color.empty()) {
    // The material first, so the OBJ never names a library that is not there.
    fs::path mtl_path = fs::path(path).replace_extension(".mtl");
    mtl_file = mtl_path.filename().string();
    const std::string text = mtl_text(path, maps);
    write_text_atomically(mtl_path, text);
  }
  const std::string text = obj_text(mesh, mtl_file);
  write_text_atomically(path, text);
}

void write_uv_mesh_ply(const std::string& path, const UVMesh& mesh) {
  validate(path, mesh);
  ply_writer(mesh).write(path);
}

void write_uv_mesh(const std::string& path, const UVMesh& mesh, const MaterialMaps& maps) {
  const std::string ext = lower_extension(path);
  if (ext == ".obj") return write_uv_mesh_obj(path, mesh, maps);
  if (ext == ".ply") return write_uv_mesh_ply(path, mesh);
  throw InputError(path,
                   "unsupported UV mesh extension '" + fs::path(path).extension().string() + "' (use .obj or .ply)");
}

UVMesh read_uv_mesh_obj(const std::string& path) {
  using Mesh = OpenMesh::PolyMesh_ArrayKernelT<>;
  Mesh m;
  m.request_halfedge_texcoords2D();
  m.request_vertex_normals();
  OpenMesh::IO::Options opt = OpenMesh::IO::Options::FaceTexCoord | OpenMesh::IO::Options::VertexNormal;
  if (!run_openmesh_reader([&] { return OpenMesh::IO::read_mesh(m, path, opt); }))
    throw InputError(path, "cannot read UV mesh (OBJ)");
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

namespace {

/// One value of a binary little-endian PLY body, as a double.
double le_value(const char* at, plyio::PlyType t) {
  auto get = [&](auto v) {
    std::memcpy(&v, at, sizeof v);  // x86 and ARM are little-endian, as the file
    return static_cast<double>(v);
  };
  switch (t) {
    case plyio::PlyType::Int8: return get(std::int8_t{});
    case plyio::PlyType::UInt8: return get(std::uint8_t{});
    case plyio::PlyType::Int16: return get(std::int16_t{});
    case plyio::PlyType::UInt16: return get(std::uint16_t{});
    case plyio::PlyType::Int32: return get(std::int32_t{});
    case plyio::PlyType::UInt32: return get(std::uint32_t{});
    case plyio::PlyType::Float32: return get(float{});
    case plyio::PlyType::Float64: return get(double{});
  }
  return 0.0;
}

}  // namespace

namespace {

/// Where the properties of a UV mesh PLY's vertices are, once its header is
/// known to be one (InputError naming the file otherwise).
struct UvPlyLayout {
  std::size_t stride = 0;
  std::vector<std::size_t> offset;  // per vertex property
  int x = -1, y = -1, z = -1, u = -1, v = -1;
  std::array<int, 3> normal{-1, -1, -1}, velocity{-1, -1, -1};
};

UvPlyLayout uv_ply_layout(const std::string& path, const plyio::PlyHeader& h) {
  if (h.format != plyio::PlyFormat::BinaryLE)
    throw InputError(path, "UV mesh PLY is not binary_little_endian (the form fluidtex writes)");
  if (h.elements.size() != 2 || h.elements[0].name != "vertex" || h.elements[1].name != "face")
    throw InputError(path, "UV mesh PLY must hold a vertex element and then a face element");
  const plyio::PlyElement &ve = h.elements[0], &fe = h.elements[1];
  UvPlyLayout l;
  for (const plyio::PlyProperty& p : ve.properties) {
    if (p.is_list) throw InputError(path, "UV mesh PLY has a list property '" + p.name + "' in its vertices");
    l.offset.push_back(l.stride);
    l.stride += static_cast<std::size_t>(plyio::type_size(p.type));
  }
  auto property = [&](const char* name) {
    const int i = ve.find(name);
    if (i < 0)
      throw InputError(path,
                       std::string("UV mesh PLY has no vertex property '") + name + "'" +
                           (name[1] == '\0' && (name[0] == 'u' || name[0] == 'v') ? " (no texture coordinates)" : ""));
    return i;
  };
  l.x = property("x"), l.y = property("y"), l.z = property("z"), l.u = property("u"), l.v = property("v");
  if (ve.find("nx") >= 0 && ve.find("ny") >= 0 && ve.find("nz") >= 0)
    l.normal = {ve.find("nx"), ve.find("ny"), ve.find("nz")};
  if (ve.find("vx") >= 0 && ve.find("vy") >= 0 && ve.find("vz") >= 0)
    l.velocity = {ve.find("vx"), ve.find("vy"), ve.find("vz")};
  if (fe.properties.size() != 1 || !fe.properties[0].is_list || plyio::is_float(fe.properties[0].type))
    throw InputError(path, "UV mesh PLY faces must hold one integer list of vertex indices");
  return l;
}

}  // namespace

UVMesh read_uv_mesh_ply(const std::string& path) {
  static_assert(std::endian::native == std::endian::little, "le_value reads little-endian values in place");
  const std::string bytes = read_file_bytes(path);
  const plyio::PlyHeader h = plyio::parse_ply_header(path, bytes);
  const UvPlyLayout l = uv_ply_layout(path, h);
  const plyio::PlyElement &ve = h.elements[0], &fe = h.elements[1];
  const plyio::PlyProperty& list = fe.properties[0];
  const std::size_t count_size = static_cast<std::size_t>(plyio::type_size(list.count_type));
  const std::size_t index_size = static_cast<std::size_t>(plyio::type_size(list.type));
  auto truncated = [&] {
    return InputError(path, "truncated binary body (the header promises " + std::to_string(ve.count) +
                                " vertices and " + std::to_string(fe.count) + " faces)");
  };

  std::size_t at = h.body_offset;
  if ((bytes.size() - at) / std::max<std::size_t>(l.stride, 1) < ve.count) throw truncated();
  UVMesh out;
  auto value = [&](const char* r, int k) { return le_value(r + l.offset[k], ve.properties[k].type); };
  auto vec3 = [&](const char* r, const std::array<int, 3>& k) {
    return Vec3(value(r, k[0]), value(r, k[1]), value(r, k[2]));
  };
  for (std::size_t i = 0; i < ve.count; ++i, at += l.stride) {
    const char* r = bytes.data() + at;
    out.positions.push_back(vec3(r, {l.x, l.y, l.z}));
    out.uvs.emplace_back(value(r, l.u), value(r, l.v));
    if (l.normal[0] >= 0) out.normals.push_back(vec3(r, l.normal));
    if (l.velocity[0] >= 0) out.velocities.push_back(vec3(r, l.velocity));
    if (!out.positions.back().allFinite() || !out.uvs.back().allFinite())
      throw InputError(path, "vertex " + std::to_string(i) + " has a non-finite position or texture coordinate");
  }
  for (std::size_t f = 0; f < fe.count; ++f) {
    if (bytes.size() - at < count_size) throw truncated();
    const long long n = plyio::read_count(bytes, at, list.count_type, false);
    at += count_size;
    if (n < 3 || n > kMaxPolygonCorners)
      throw InputError(path, "face " + std::to_string(f) + " has " + std::to_string(n) + " corners");
    if ((bytes.size() - at) / index_size < static_cast<std::size_t>(n)) throw truncated();
    std::vector<int> corner(static_cast<std::size_t>(n));
    for (int& c : corner) {
      const double index = le_value(bytes.data() + at, list.type);
      at += index_size;
      if (!(index >= 0.0 && index < static_cast<double>(ve.count)))
        throw InputError(path, "face " + std::to_string(f) + " names vertex " + std::to_string(std::llround(index)) +
                                   " of " + std::to_string(ve.count));
      c = static_cast<int>(index);
    }
    for (std::size_t k = 1; k + 1 < corner.size(); ++k) out.triangles.push_back({corner[0], corner[k], corner[k + 1]});
  }
  out.uv_triangles = out.triangles;  // one uv per (split) vertex
  return out;
}

UVMesh read_uv_mesh(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".obj") return read_uv_mesh_obj(path);
  if (ext == ".ply") return read_uv_mesh_ply(path);
  throw InputError(path,
                   "unsupported UV mesh extension '" + fs::path(path).extension().string() + "' (use .obj or .ply)");
}

}  // namespace fluidtex
