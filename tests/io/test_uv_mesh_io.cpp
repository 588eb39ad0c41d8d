// UV meshes (io/uv_mesh_io.h): OBJ and PLY written and read back through
// OpenMesh and the reader, material, precision, velocities, errors.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "fluidtex/io/mesh_io.h"
#include "fluidtex/io/uv_mesh_io.h"
#include "fluidtex/util/error.h"
#include "test_util.h"

namespace fluidtex {
namespace {

using test::list_dir;
using test::read_file;
using test::TempDir;
using test::write_file;

/// A 2x1 quad strip split into two charts along the edge 1-4 (a seam):
///   3---4---5
///   | A | B |
///   0---1---2
/// Vertices 1 and 4 carry one uv per chart: 8 distinct (vertex, uv) pairs.
UVMesh seam_mesh() {
  UVMesh m;
  m.positions = {Vec3(0, 0, 0),           Vec3(1, 0, 0),   Vec3(2, 0, 0.25),
                 Vec3(0, 1, 0.123456789), Vec3(1, 1, 0.5), Vec3(2, 1, -1e-3)};
  m.normals.assign(6, Vec3(0, 0, 1));
  m.normals[2] = Vec3(0.6, 0, 0.8);
  m.triangles = {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}};
  m.uvs = {Vec2(0.0, 0.0), Vec2(0.4, 0.0), Vec2(0.4, 0.4), Vec2(0.0, 0.4),   // chart A
           Vec2(0.6, 0.6), Vec2(1.0, 0.6), Vec2(1.0, 1.0), Vec2(0.6, 1.0)};  // chart B
  m.uv_triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
  return m;
}

using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;

TEST(UvMeshWriterObj, RoundTripThroughOpenMesh) {
  TempDir dir;
  const UVMesh m = seam_mesh();
  const std::string path = dir.file("frame.obj");
  write_uv_mesh_obj(path, m, "atlas_0001.png");
  EXPECT_EQ(list_dir(dir.path()), (std::vector<std::string>{"frame.mtl", "frame.obj"}));

  OMesh om;
  om.request_halfedge_texcoords2D();
  om.request_vertex_normals();
  OpenMesh::IO::Options opt = OpenMesh::IO::Options::FaceTexCoord | OpenMesh::IO::Options::VertexNormal;
  ASSERT_TRUE(OpenMesh::IO::read_mesh(om, path, opt));
  ASSERT_EQ(om.n_vertices(), m.positions.size());
  ASSERT_EQ(om.n_faces(), m.triangles.size());
  EXPECT_TRUE(opt.face_has_texcoord());
  for (size_t v = 0; v < m.positions.size(); ++v) {
    const auto p = om.point(OMesh::VertexHandle(static_cast<int>(v)));
    for (int i = 0; i < 3; ++i) EXPECT_EQ(p[i], static_cast<float>(m.positions[v][i])) << v;
  }
  for (size_t f = 0; f < m.triangles.size(); ++f) {
    int corners = 0;
    for (auto h : om.fh_range(OMesh::FaceHandle(static_cast<int>(f)))) {
      const int v = om.to_vertex_handle(h).idx();
      const auto& tri = m.triangles[f];
      const int k = static_cast<int>(std::find(tri.begin(), tri.end(), v) - tri.begin());
      ASSERT_LT(k, 3) << "face " << f << " lost vertex " << v;
      const Vec2& uv = m.uvs[m.uv_triangles[f][k]];
      const auto t = om.texcoord2D(h);
      EXPECT_EQ(t[0], static_cast<float>(uv.x())) << f << "/" << k;
      EXPECT_EQ(t[1], static_cast<float>(uv.y())) << f << "/" << k;
      ++corners;
    }
    EXPECT_EQ(corners, 3);
  }
}

TEST(UvMeshWriterObj, FaceTripletsAndMaterial) {
  TempDir dir;
  const UVMesh m = seam_mesh();
  const std::string path = dir.file("frame.obj");
  write_uv_mesh_obj(path, m, (dir.path() / "atlas_0001.png").string());
  std::vector<std::string> face_lines;
  int v = 0, vt = 0, vn = 0;
  bool mtllib = false, usemtl = false;
  for (const std::string& line : test::lines_of(read_file(path))) {
    if (line.rfind("v ", 0) == 0) ++v;
    if (line.rfind("vt ", 0) == 0) ++vt;
    if (line.rfind("vn ", 0) == 0) ++vn;
    if (line == "mtllib frame.mtl") mtllib = true;
    if (line == "usemtl fluidtex_atlas") usemtl = true;
    if (line.rfind("f ", 0) == 0) face_lines.push_back(line);
  }
  EXPECT_EQ(v, 6);
  EXPECT_EQ(vt, 8);
  EXPECT_EQ(vn, 6);
  EXPECT_TRUE(mtllib);
  EXPECT_TRUE(usemtl);
  ASSERT_EQ(face_lines.size(), m.triangles.size());
  for (size_t f = 0; f < face_lines.size(); ++f) {
    std::istringstream in(face_lines[f].substr(2));
    for (int k = 0; k < 3; ++k) {
      int a = 0, b = 0, c = 0;
      char s1 = 0, s2 = 0;
      in >> a >> s1 >> b >> s2 >> c;
      EXPECT_EQ(s1, '/');
      EXPECT_EQ(s2, '/');
      EXPECT_EQ(a, m.triangles[f][k] + 1) << face_lines[f];
      EXPECT_EQ(b, m.uv_triangles[f][k] + 1) << face_lines[f];
      EXPECT_EQ(c, m.triangles[f][k] + 1) << face_lines[f];
    }
  }
  const std::string mtl = read_file(dir.file("frame.mtl"));
  EXPECT_NE(mtl.find("newmtl fluidtex_atlas\n"), std::string::npos);
  EXPECT_NE(mtl.find("map_Kd atlas_0001.png\n"), std::string::npos) << mtl;  // made relative
  EXPECT_EQ(mtl.find("disp"), std::string::npos) << mtl;
  EXPECT_EQ(mtl.find("norm"), std::string::npos) << mtl;

  // Height and normal atlases: disp, bump with its multiplier, norm.
  MaterialMaps maps((dir.path() / "atlas_0001.exr").string());
  maps.displacement = (dir.path() / "maps" / "height_0001.exr").string();
  maps.normal = "normal_0001.exr";
  maps.bump_height = 0.0125;
  write_uv_mesh_obj(path, m, maps);
  const std::vector<std::string> lines = test::lines_of(read_file(dir.file("frame.mtl")));
  for (const char* expected : {"map_Kd atlas_0001.exr", "disp maps/height_0001.exr",
                               "bump -bm 0.0125 maps/height_0001.exr", "norm normal_0001.exr"}) {
    EXPECT_NE(std::find(lines.begin(), lines.end(), expected), lines.end()) << expected;
  }
}

TEST(UvMeshWriterObj, PositionsKeepFloatPrecision) {
  TempDir dir;
  write_uv_mesh(dir.file("m.OBJ"), seam_mesh());
  const std::string text = read_file(dir.file("m.OBJ"));
  EXPECT_NE(text.find("v 0 1 0.12345679\n"), std::string::npos) << text;
  EXPECT_NE(text.find("v 2 1 -0.001\n"), std::string::npos) << text;
  EXPECT_NE(text.find("vt 0.4 0\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("mtllib"), std::string::npos);
}

TEST(UvMeshWriterPly, CarriesVelocitiesForMotionBlur) {
  TempDir dir;
  UVMesh m = seam_mesh();
  for (std::size_t v = 0; v < m.positions.size(); ++v) m.velocities.emplace_back(0.5 * v, -1.0, 0.25);
  const std::string path = dir.file("frame.ply");
  write_uv_mesh_ply(path, m);
  EXPECT_NE(read_file(path).find("property float v\nproperty float vx\nproperty float vy\nproperty float vz\n"),
            std::string::npos);
  // fluidtex's own reader takes them as the vertices' velocities (seam
  // copies of a vertex carry its velocity).
  ReadOptions read;
  read.clean = false;
  const FrameMesh back = read_frame(path, read);
  ASSERT_EQ(back.velocities.size(), back.positions.size());
  for (std::size_t i = 0; i < back.positions.size(); ++i) {
    const auto same_place = [&](const Vec3& p) { return p.cast<float>().cast<double>() == back.positions[i]; };
    const auto v = std::find_if(m.positions.begin(), m.positions.end(), same_place) - m.positions.begin();
    ASSERT_LT(v, static_cast<long>(m.positions.size())) << i;
    EXPECT_EQ(back.velocities[i], m.velocities[v].cast<float>().cast<double>()) << i;
  }
  // Without velocities the header is the plain one.
  write_uv_mesh_ply(dir.file("plain.ply"), seam_mesh());
  EXPECT_EQ(read_file(dir.file("plain.ply")).find("vx"), std::string::npos);
}

TEST(UvMeshWriterPly, RoundTripThroughOpenMesh) {
  TempDir dir;
  const UVMesh m = seam_mesh();
  const std::string path = dir.file("frame.ply");
  write_uv_mesh_ply(path, m);
  EXPECT_EQ(read_file(path).rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);

  // Expected split: distinct (vertex, uv index) pairs, sorted.
  std::vector<std::pair<int, int>> pairs;
  for (size_t f = 0; f < m.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) pairs.emplace_back(m.triangles[f][k], m.uv_triangles[f][k]);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  ASSERT_EQ(pairs.size(), 8u);

  OMesh om;
  om.request_vertex_texcoords2D();
  om.request_vertex_normals();
  OpenMesh::IO::Options opt =
      OpenMesh::IO::Options::VertexTexCoord | OpenMesh::IO::Options::VertexNormal | OpenMesh::IO::Options::Binary;
  ASSERT_TRUE(OpenMesh::IO::read_mesh(om, path, opt));
  ASSERT_EQ(om.n_vertices(), pairs.size());
  ASSERT_EQ(om.n_faces(), m.triangles.size());
  EXPECT_TRUE(opt.vertex_has_texcoord());
  EXPECT_TRUE(opt.vertex_has_normal());
  for (size_t i = 0; i < pairs.size(); ++i) {
    const OMesh::VertexHandle vh(static_cast<int>(i));
    const auto [v, uvi] = pairs[i];
    const auto p = om.point(vh);
    const auto n = om.normal(vh);
    const auto t = om.texcoord2D(vh);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(p[c], static_cast<float>(m.positions[v][c])) << i;
      EXPECT_EQ(n[c], static_cast<float>(m.normals[v][c])) << i;
    }
    EXPECT_EQ(t[0], static_cast<float>(m.uvs[uvi].x())) << i;
    EXPECT_EQ(t[1], static_cast<float>(m.uvs[uvi].y())) << i;
  }
  // Each face's corners carry the uv of that corner.
  for (size_t f = 0; f < m.triangles.size(); ++f)
    for (auto vh : om.fv_range(OMesh::FaceHandle(static_cast<int>(f)))) {
      const auto [v, uvi] = pairs[vh.idx()];
      const auto& tri = m.triangles[f];
      const int k = static_cast<int>(std::find(tri.begin(), tri.end(), v) - tri.begin());
      ASSERT_LT(k, 3);
      EXPECT_EQ(m.uv_triangles[f][k], uvi);
    }
}

/// Each corner of `a` and of `b` at the same place with the same uv (to
/// float precision): the same textured surface, whatever the vertex split.
void expect_same_corners(const UVMesh& a, const UVMesh& b) {
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  for (std::size_t f = 0; f < a.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(a.positions[a.triangles[f][k]].cast<float>(), b.positions[b.triangles[f][k]].cast<float>()) << f;
      EXPECT_EQ(a.uvs[a.uv_triangles[f][k]].cast<float>(), b.uvs[b.uv_triangles[f][k]].cast<float>()) << f;
      if (!a.normals.empty() && !b.normals.empty())
        EXPECT_EQ(a.normals[a.triangles[f][k]].cast<float>(), b.normals[b.triangles[f][k]].cast<float>()) << f;
    }
}

TEST(UvMeshReader, ReadsThePlyAndTheObjTheWritersWrite) {
  TempDir dir;
  UVMesh m = seam_mesh();
  for (std::size_t v = 0; v < m.positions.size(); ++v) m.velocities.emplace_back(0.5 * v, -1.0, 0.25);
  write_uv_mesh(dir.file("m.ply"), m);
  write_uv_mesh(dir.file("m.obj"), m);
  const UVMesh ply = read_uv_mesh(dir.file("m.ply")), obj = read_uv_mesh(dir.file("m.obj"));
  expect_same_corners(m, ply);
  expect_same_corners(m, obj);
  EXPECT_EQ(ply.positions.size(), 8u);  // split at the seam: one vertex per (vertex, uv)
  ASSERT_EQ(ply.velocities.size(), ply.positions.size());
  for (std::size_t f = 0; f < m.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(ply.velocities[ply.triangles[f][k]], m.velocities[m.triangles[f][k]].cast<float>().cast<double>());
  // A non-manifold frame (three faces on an edge) passes through as written.
  UVMesh fan;
  fan.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1)};
  fan.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  fan.uvs = {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1), Vec2(0.5, 0.5), Vec2(1, 1)};
  fan.uv_triangles = fan.triangles;
  write_uv_mesh(dir.file("fan.ply"), fan);
  expect_same_corners(fan, read_uv_mesh(dir.file("fan.ply")));
}

TEST(UvMeshReader, RefusesWhatIsNotAUvMeshInOneLine) {
  TempDir dir;
  write_uv_mesh(dir.file("m.ply"), seam_mesh());
  const std::string good = read_file(dir.file("m.ply"));
  auto refusal = [&](const std::string& name, const std::string& bytes) {
    test::write_file(dir.path() / name, bytes);
    try {
      read_uv_mesh(dir.file(name));
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      EXPECT_NE(what.find(name), std::string::npos) << what;
      return what;
    }
    ADD_FAILURE() << name << " was read";
    return std::string();
  };
  EXPECT_NE(refusal("short.ply", good.substr(0, good.size() - 5)).find("truncated"), std::string::npos);
  EXPECT_NE(refusal("body.ply", good.substr(0, good.find("end_header\n") + 20)).find("truncated"), std::string::npos);
  // An input frame (positions and velocities, no uv) is not a UV mesh.
  const std::string frame =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nproperty float vx\nproperty float vy\nproperty float vz\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n" +
      std::string(3 * 6 * 4, '\0') + std::string("\x03\0\0\0\0\x01\0\0\0\x02\0\0\0", 13);
  EXPECT_NE(refusal("frame.ply", frame).find("no texture coordinates"), std::string::npos);
  std::string far = good;
  far[far.size() - 4] = '\x7f';  // the last corner's index, far past the vertices
  EXPECT_NE(refusal("far.ply", far).find("names vertex"), std::string::npos);
  std::string nan = good;
  const std::size_t body = nan.find("end_header\n") + 11;
  for (int i = 0; i < 4; ++i) nan[body + i] = "\x00\x00\xc0\x7f"[i];  // the first x: a quiet NaN
  EXPECT_NE(refusal("nan.ply", nan).find("non-finite"), std::string::npos);
  EXPECT_NE(refusal("ascii.ply", "ply\nformat ascii 1.0\nelement vertex 0\nend_header\n").find("binary"),
            std::string::npos);
  EXPECT_NE(refusal("m.stl", good).find("use .obj or .ply"), std::string::npos);
  EXPECT_THROW(read_uv_mesh(dir.file("missing.ply")), InputError);
}

TEST(UvMeshWriterPly, NonManifoldFramePassesThrough) {
  // Three triangles on one edge (non-manifold) and an isolated vertex.
  UVMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(5, 5, 5)};
  m.normals.assign(6, Vec3(0, 0, 1));
  m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  m.uvs = {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1), Vec2(0.5, 0.5), Vec2(1, 1)};
  m.uv_triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  TempDir dir;
  write_uv_mesh(dir.file("nm.ply"), m);
  write_uv_mesh(dir.file("nm.obj"), m);
  const std::string ply = read_file(dir.file("nm.ply"));
  EXPECT_NE(ply.find("element vertex 6\n"), std::string::npos);  // 5 used + 1 isolated
  EXPECT_NE(ply.find("element face 3\n"), std::string::npos);
  const size_t header = ply.find("end_header\n") + 11;
  EXPECT_EQ(ply.size(), header + 6 * 8 * 4 + 3 * 13);
  const std::string obj = read_file(dir.file("nm.obj"));
  const auto obj_lines = test::lines_of(obj);
  EXPECT_EQ(
      std::count_if(obj_lines.begin(), obj_lines.end(), [](const std::string& l) { return l.rfind("f ", 0) == 0; }), 3);
}

TEST(UvMeshWriterErrors, UnsupportedExtensionAndBadMesh) {
  TempDir dir;
  EXPECT_THROW(write_uv_mesh(dir.file("frame.stl"), seam_mesh()), InputError);
  UVMesh bad = seam_mesh();
  bad.triangles[0][1] = 42;
  EXPECT_THROW(write_uv_mesh(dir.file("bad.obj"), bad), InternalError);
  bad = seam_mesh();
  bad.uv_triangles.pop_back();
  EXPECT_THROW(write_uv_mesh(dir.file("bad.ply"), bad), InternalError);
  EXPECT_TRUE(list_dir(dir.path()).empty());
}

TEST(UvMeshWriterDeterminism, SameMeshSameBytes) {
  TempDir dir;
  for (const std::string ext : {".obj", ".ply"}) {
    write_uv_mesh(dir.file("a" + ext), seam_mesh());
    write_uv_mesh(dir.file("b" + ext), seam_mesh());
    EXPECT_EQ(read_file(dir.file("a" + ext)), read_file(dir.file("b" + ext)));
  }
  EXPECT_EQ(list_dir(dir.path()), (std::vector<std::string>{"a.obj", "a.ply", "b.obj", "b.ply"}));
}

}  // namespace
}  // namespace fluidtex
