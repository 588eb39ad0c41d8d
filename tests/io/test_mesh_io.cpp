// Tests of mesh_io (reading PLY/OBJ frames) and mesh_clean. All files are
// written here, byte by byte, into a TempDir.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>
#include <thread>

#include "fluidtex/io/mesh_io.h"
#include "fluidtex/util/error.h"
#include "test_util.h"

namespace fluidtex {
namespace {

using test::TempDir;
using test::write_file;
using Polygons = std::vector<std::vector<int>>;

// --- Writing test PLY files -------------------------------------------------------------

struct PlySpec {
  std::string format = "ascii";  ///< or binary_little_endian / binary_big_endian
  std::string pos_type = "float";
  std::string vel_type = "float";
  std::vector<std::string> vel_names = {"vx", "vy", "vz"};  ///< empty: no velocities
  std::string count_type = "uchar";
  std::string index_type = "int";
  std::string list_name = "vertex_indices";
};

/// Appends `value` converted to PLY type `type`, in ASCII or binary.
void put(std::string& out, const PlySpec& s, const std::string& type, double value) {
  if (s.format == "ascii") {
    std::ostringstream o;
    o.precision(17);
    if (type == "float")
      o << static_cast<double>(static_cast<float>(value));
    else
      o << value;
    out += o.str() + " ";
    return;
  }
  char b[8];
  int n = 0;
  auto store = [&](auto v) {
    n = sizeof(v);
    std::memcpy(b, &v, sizeof(v));
  };
  if (type == "float")
    store(static_cast<float>(value));
  else if (type == "double")
    store(value);
  else if (type == "uchar" || type == "uint8")
    store(static_cast<std::uint8_t>(value));
  else if (type == "char" || type == "int8")
    store(static_cast<std::int8_t>(value));
  else if (type == "ushort" || type == "uint16")
    store(static_cast<std::uint16_t>(value));
  else if (type == "short" || type == "int16")
    store(static_cast<std::int16_t>(value));
  else if (type == "uint" || type == "uint32")
    store(static_cast<std::uint32_t>(value));
  else
    store(static_cast<std::int32_t>(value));
  if (s.format == "binary_big_endian") std::reverse(b, b + n);
  out.append(b, n);
}

std::string make_ply(const PlySpec& s, const std::vector<Vec3>& pos, const std::vector<Vec3>& vel,
                     const Polygons& faces) {
  std::string h = "ply\nformat " + s.format + " 1.0\ncomment made by test_mesh_io\n";
  h += "element vertex " + std::to_string(pos.size()) + "\n";
  for (const char* a : {"x", "y", "z"}) h += "property " + s.pos_type + " " + a + "\n";
  for (const std::string& n : s.vel_names) h += "property " + s.vel_type + " " + n + "\n";
  h += "element face " + std::to_string(faces.size()) + "\n";
  h += "property list " + s.count_type + " " + s.index_type + " " + s.list_name + "\nend_header\n";
  std::string body;
  for (std::size_t i = 0; i < pos.size(); ++i) {
    for (int a = 0; a < 3; ++a) put(body, s, s.pos_type, pos[i][a]);
    for (std::size_t a = 0; a < s.vel_names.size(); ++a) put(body, s, s.vel_type, vel[i][a]);
    if (s.format == "ascii") body += "\n";
  }
  for (const auto& f : faces) {
    put(body, s, s.count_type, static_cast<double>(f.size()));
    for (int v : f) put(body, s, s.index_type, v);
    if (s.format == "ascii") body += "\n";
  }
  return h + body;
}

/// A flat (z = 0.1) fan of a square, a pentagon and a triangle: 7 vertices,
/// 6 triangles, area 2.5, all facing +z. Values like 0.1 and 1/3 are not
/// exact in float, so they tell float and double apart.
struct Sample {
  std::vector<Vec3> pos = {{0, 0, 0.1}, {1, 0, 0.1}, {1, 1, 0.1},    {0, 1, 0.1},
                           {2, 0, 0.1}, {2, 1, 0.1}, {1.5, 1.5, 0.1}};
  std::vector<Vec3> vel;
  Polygons faces = {{0, 1, 2, 3}, {1, 4, 5, 6, 2}, {3, 2, 6}};
  Sample() {
    for (int i = 0; i < 7; ++i) vel.emplace_back(0.1 * i + 1.0 / 3.0, -i, 1e-3 * i);
  }
};

double as_type(double v, const std::string& type) {
  return type == "float" ? static_cast<double>(static_cast<float>(v)) : v;
}

void expect_facing_up(const FrameMesh& m, double area) {
  EXPECT_NEAR(surface_area(m), area, 1e-6);
  for (std::size_t f = 0; f < m.num_faces(); ++f) EXPECT_GT(face_area_normal(m, f).z(), 0.0) << "face " << f;
}

/// The what() of the InputError read_frame throws (fails if none is thrown).
std::string read_error(const std::string& path, const ReadOptions& opt = {}) {
  try {
    read_frame(path, opt);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(std::filesystem::path(path).filename().string()), std::string::npos)
        << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << path;
  return "";
}

// --- Round trips -----------------------------------------------------------------------

TEST(MeshIo, RoundTripsEveryFormatTypeAndVelocityNaming) {
  TempDir dir;
  const Sample s;
  const std::vector<std::vector<std::string>> namings = {
      {"vx", "vy", "vz"}, {"velocity_x", "velocity_y", "velocity_z"}, {"v_x", "v_y", "v_z"}};
  int n = 0;
  for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    for (const char* type : {"float", "double"}) {
      for (const auto& names : namings) {
        PlySpec spec;
        spec.format = format;
        spec.pos_type = spec.vel_type = type;
        spec.vel_names = names;
        SCOPED_TRACE(std::string(format) + " " + type + " " + names[0]);
        const std::string path = dir.file("f" + std::to_string(n++) + ".ply");
        write_file(path, make_ply(spec, s.pos, s.vel, s.faces));
        CleanReport report;
        const FrameMesh m = read_frame(path, {}, &report);
        ASSERT_EQ(m.num_vertices(), 7u);
        ASSERT_EQ(m.num_faces(), 6u);
        for (int i = 0; i < 7; ++i)
          for (int a = 0; a < 3; ++a) {
            EXPECT_EQ(m.positions[i][a], as_type(s.pos[i][a], type)) << "vertex " << i;
            EXPECT_EQ(m.velocities[i][a], as_type(s.vel[i][a], type)) << "vertex " << i;
          }
        expect_facing_up(m, 2.5);
        EXPECT_FALSE(report.changed()) << report.summary();
      }
    }
  }
}

TEST(MeshIo, AsciiWithoutFinalNewlineAndWithCrlfHeader) {
  TempDir dir;
  const Sample s;
  std::string ply = make_ply({}, s.pos, s.vel, s.faces);
  ply.pop_back();  // no newline after the last face
  const std::size_t body = ply.find("end_header\n") + 11;
  std::string header = ply.substr(0, body), crlf;
  for (char c : header) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  write_file(dir.file("a.ply"), crlf + ply.substr(body));
  const FrameMesh m = read_frame(dir.file("a.ply"));
  EXPECT_EQ(m.num_faces(), 6u);
  EXPECT_EQ(m.velocities[6], s.vel[6].cast<float>().cast<double>());
}

TEST(MeshIo, ConcaveQuadIsNotInverted) {
  TempDir dir;
  // A dart: vertex 1 is reflex, so a fan from vertex 0 would flip a triangle.
  const std::vector<Vec3> pos = {{0, 0, 0}, {1, 0.3, 0}, {2, 0, 0}, {1, 2, 0}};
  const std::vector<Vec3> vel(4, Vec3(1, 2, 3));
  write_file(dir.file("dart.ply"), make_ply({}, pos, vel, {{0, 1, 2, 3}}));
  const FrameMesh m = read_frame(dir.file("dart.ply"));
  ASSERT_EQ(m.num_faces(), 2u);
  expect_facing_up(m, 1.7);
}

TEST(MeshIo, AcceptsAnyListTypesAndVertexIndexName) {
  TempDir dir;
  const Sample s;
  const std::vector<std::pair<std::string, std::string>> types = {
      {"char", "uint"}, {"ushort", "short"}, {"uint", "ushort"}, {"int32", "uint8"}, {"uint16", "int16"}};
  int n = 0;
  for (const char* format : {"binary_little_endian", "binary_big_endian", "ascii"}) {
    for (const auto& [count, index] : types) {
      PlySpec spec;
      spec.format = format;
      spec.count_type = count;
      spec.index_type = index;
      spec.list_name = n % 2 ? "vertex_index" : "vertex_indices";
      SCOPED_TRACE(std::string(format) + " list " + count + " " + index);
      const std::string path = dir.file("l" + std::to_string(n++) + ".ply");
      write_file(path, make_ply(spec, s.pos, s.vel, s.faces));
      const FrameMesh m = read_frame(path);
      EXPECT_EQ(m.num_faces(), 6u);
      EXPECT_EQ(m.velocities[6], s.vel[6].cast<float>().cast<double>());
    }
  }
}

TEST(MeshIo, CustomVelocityAttribute) {
  TempDir dir;
  const Sample s;
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"vel_x", "vel_y", "vel_z"}, "vel"},
      {{"Vx", "Vy", "Vz"}, "V"},
      {{"u", "red", "nx"}, "u, red ,nx"}};  // names OpenMesh would otherwise treat specially
  int n = 0;
  for (const auto& [names, attr] : cases) {
    PlySpec spec;
    spec.format = "binary_little_endian";
    spec.vel_names = names;
    const std::string path = dir.file("c" + std::to_string(n++) + ".ply");
    write_file(path, make_ply(spec, s.pos, s.vel, s.faces));
    ReadOptions opt;
    opt.velocity_attr = attr;
    const FrameMesh m = read_frame(path, opt);
    EXPECT_EQ(m.velocities[3], s.vel[3].cast<float>().cast<double>()) << attr;
    EXPECT_NE(read_error(path).find("--velocity-attr"), std::string::npos);  // auto-detect fails
  }
}

TEST(MeshIo, VelocitiesNotRequiredGivesZeros) {
  TempDir dir;
  const Sample s;
  PlySpec spec;
  spec.vel_names = {};
  write_file(dir.file("novel.ply"), make_ply(spec, s.pos, s.vel, s.faces));
  ReadOptions opt;
  opt.require_velocities = false;
  const FrameMesh m = read_frame(dir.file("novel.ply"), opt);
  EXPECT_EQ(m.num_faces(), 6u);
  for (const Vec3& v : m.velocities) EXPECT_EQ(v, Vec3::Zero());
}

TEST(MeshIo, ObjOnlyWithoutRequiredVelocities) {
  TempDir dir;
  const std::string path = dir.file("quad.OBJ");
  write_file(path,
             "# quad and triangle\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 2 0\n"
             "f 1 2 3 4\nf 4 3 5\n");
  ReadOptions opt;
  opt.require_velocities = false;
  const FrameMesh m = read_frame(path, opt);
  EXPECT_EQ(m.num_vertices(), 5u);
  EXPECT_EQ(m.num_faces(), 3u);
  EXPECT_EQ(m.positions[4], Vec3(0.5, 2, 0));
  expect_facing_up(m, 1.5);
  const std::string err = read_error(path);
  EXPECT_NE(err.find("OBJ cannot carry velocities"), std::string::npos) << err;
  EXPECT_NE(err.find("--velocity-from-positions"), std::string::npos) << err;
}

TEST(MeshIo, AHeaderWithoutEndHeaderSaysSoWithoutEchoingTheBody) {
  // The body of an ASCII file, or binary bytes, where the header's next
  // keyword should be: the line says end_header is missing, and no byte of
  // the body is echoed.
  TempDir dir;
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
  write_file(dir.file("ascii.ply"), head + "0.5 0 0\n1 0 0\n0 1 0\n");
  std::string err = read_error(dir.file("ascii.ply"));
  EXPECT_NE(err.find("line 7: numbers before end_header (is the end_header line missing?)"), std::string::npos) << err;
  write_file(dir.file("garbage.ply"), head + "\x81\x82junk\n");
  err = read_error(dir.file("garbage.ply"));
  EXPECT_NE(err.find("binary data before end_header"), std::string::npos) << err;
  EXPECT_EQ(err.find("junk"), std::string::npos) << err;
  write_file(dir.file("keyword.ply"), head + "vertex_count 3\nend_header\n");
  err = read_error(dir.file("keyword.ply"));
  EXPECT_NE(err.find("unknown keyword 'vertex_count'"), std::string::npos) << err;
}

TEST(MeshIo, ADamagedFrameIsNotTakenForAFrameWithoutLiquid) {
  // A frame without liquid (no vertices) is told apart from a damaged one:
  // binary bytes in an OBJ, faces of fewer than three corners, every vertex
  // at one point.
  TempDir dir;
  const std::string no_velocity = "--velocity-from-positions";
  ReadOptions positions_only;
  positions_only.require_velocities = false;
  write_file(dir.file("empty.obj"), "# nothing this frame\n");
  EXPECT_NE(read_error(dir.file("empty.obj"), positions_only).find("a frame without liquid"), std::string::npos);
  // Damaged past its first line, no NUL byte (those are refused on sight).
  write_file(dir.file("binary.obj"), "# exported\n\x7f\x45\x4c\x46\x02\x01\x01\x81\x92 garbage\n");
  std::string err = read_error(dir.file("binary.obj"), positions_only);
  EXPECT_NE(err.find("not a text OBJ (binary bytes, no vertex line)"), std::string::npos) << err;
  EXPECT_EQ(err.find("without liquid"), std::string::npos) << err;
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nproperty float vx\nproperty float vy\nproperty float vz\n"
      "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
  write_file(dir.file("lines.ply"), head + "0 0 0 0 0 0\n1 0 0 0 0 0\n0 1 0 0 0 0\n2 0 1\n2 1 2\n");
  err = read_error(dir.file("lines.ply"));
  EXPECT_NE(err.find("no triangles: all 2 faces have fewer than three corners"), std::string::npos) << err;
  write_file(dir.file("point.ply"), head + "1 2 3 0 0 0\n1 2 3 0 0 0\n1 2 3 0 0 0\n3 0 1 2\n3 0 2 1\n");
  err = read_error(dir.file("point.ply"));
  EXPECT_NE(err.find("no surface: every vertex lies at one point (1, 2, 3)"), std::string::npos) << err;
}

TEST(MeshIo, ConcurrentReadsAgree) {
  TempDir dir;
  const Sample s;
  PlySpec spec;
  spec.format = "binary_big_endian";
  spec.vel_type = "double";
  write_file(dir.file("a.ply"), make_ply(spec, s.pos, s.vel, s.faces));
  write_file(dir.file("b.ply"), make_ply({}, s.pos, s.vel, s.faces));
  std::vector<std::thread> threads;
  std::atomic<int> good{0};
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < 25; ++i) {
        const FrameMesh m = read_frame(dir.file((t + i) % 2 ? "a.ply" : "b.ply"));
        if (m.num_faces() == 6 && m.velocities[1].x() == as_type(s.vel[1].x(), (t + i) % 2 ? "double" : "float"))
          ++good;
      }
    });
  }
  for (auto& th : threads) th.join();
  EXPECT_EQ(good.load(), 100);
}

// --- Bad input -------------------------------------------------------------------------

TEST(MeshIo, BadInputGivesOneLineErrors) {
  TempDir dir;
  const Sample s;
  auto expect_error = [&](const std::string& name, const std::string& bytes, const std::string& word,
                          const ReadOptions& opt = {}) {
    SCOPED_TRACE(name);
    const std::string path = dir.file(name);
    if (!bytes.empty()) write_file(path, bytes);
    const std::string err = read_error(path, opt);
    EXPECT_NE(err.find(word), std::string::npos) << err;
    EXPECT_EQ(err.find('\n'), std::string::npos) << err;
    if (std::getenv("FLUIDTEX_SHOW_ERRORS")) std::cout << err << "\n";
  };
  PlySpec bin;
  bin.format = "binary_little_endian";
  const std::string good_bin = make_ply(bin, s.pos, s.vel, s.faces);
  const std::string good_ascii = make_ply({}, s.pos, s.vel, s.faces);

  expect_error("missing.ply", "", "missing");
  expect_error("mesh.stl", "solid x\n", "unknown mesh format");
  expect_error("magic.ply", "hello world\n", "magic");
  expect_error("header.ply", good_bin.substr(0, 60), "truncated");
  expect_error("cut_faces.ply", good_bin.substr(0, good_bin.size() - 5), "truncated");
  expect_error("cut_vertices.ply", good_bin.substr(0, good_bin.find("end_header") + 60), "truncated");
  expect_error("cut_ascii.ply", good_ascii.substr(0, good_ascii.size() - 8), "truncated");
  expect_error("cut_ascii_vertices.ply", good_ascii.substr(0, good_ascii.find("end_header") + 40), "truncated");

  PlySpec uchar_vel = bin;
  uchar_vel.vel_type = "uchar";
  expect_error("uchar_vel.ply", make_ply(uchar_vel, s.pos, s.vel, s.faces), "wrong property type for velocity");
  PlySpec int_pos = bin;
  int_pos.pos_type = "int";
  expect_error("int_pos.ply", make_ply(int_pos, s.pos, s.vel, s.faces), "wrong property type for position");
  PlySpec float_idx = bin;
  float_idx.index_type = "float";
  expect_error("float_idx.ply", make_ply(float_idx, s.pos, s.vel, s.faces), "type");

  PlySpec no_vel;
  no_vel.vel_names = {"speed_x", "speed_y", "speed_z"};
  expect_error("novel.ply", make_ply(no_vel, s.pos, s.vel, s.faces), "no velocity properties (tried vx/vy/vz");

  std::vector<Vec3> bad = s.vel;
  bad[2].y() = std::numeric_limits<double>::quiet_NaN();
  expect_error("nan.ply", make_ply(bin, s.pos, bad, s.faces), "NaN in velocity of vertex 2");
  std::vector<Vec3> inf = s.pos;
  inf[5].x() = std::numeric_limits<double>::infinity();
  expect_error("inf.ply", make_ply(bin, inf, s.vel, s.faces), "Inf in position of vertex 5");

  expect_error("index.ply", make_ply(bin, s.pos, s.vel, {{0, 1, 7}}), "index 7 out of range");
  expect_error("negindex.ply", make_ply(bin, s.pos, s.vel, {{0, -1, 2}}), "index -1 out of range");
  expect_error("ascii_index.ply", make_ply({}, s.pos, s.vel, {{0, 1, 2}, {0, 2, 99}}), "index 99 out of range");

  expect_error("nofaces.ply", make_ply(bin, s.pos, s.vel, {}), "empty mesh (no faces; a frame without liquid");
  expect_error("novertices.ply", make_ply(bin, {}, {}, {}), "empty mesh (no vertices; a frame without liquid");
  // Only a zero-area triangle: nothing is left after cleaning.
  expect_error("flat.ply",
               make_ply(bin, {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, std::vector<Vec3>(3, Vec3::Zero()), {{0, 1, 2}}),
               "empty mesh");
  write_file(dir.file("zero.ply"), "");
  EXPECT_NE(read_error(dir.file("zero.ply")).find("empty"), std::string::npos);
}

// --- Cleaning --------------------------------------------------------------------------

TEST(MeshIo, AHeaderCommentStatesTheFrameRate) {
  // As exporters write it: the shared Blender caches ("fps=24"), fluidtex's
  // own Blender exporter ("fps 24,"), and other spellings a person would
  // read as a frame rate. Anything else states none.
  TempDir dir;
  auto stated = [&](const std::string& header_lines, const char* name = "f.ply") {
    const std::string path = dir.file(name);
    write_file(path, "ply\nformat ascii 1.0\n" + header_lines +
                         "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                         "property float vx\nproperty float vy\nproperty float vz\n"
                         "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                         "0 0 0 0 0 0\n1 0 0 0 0 0\n0 1 0 0 0 0\n3 0 1 2\n");
    return read_stated_fps(path);
  };
  EXPECT_EQ(stated("comment Blender 3.4.1 Mantaflow FLIP liquid surface, scene=slosh frame=1 fps=24\n"), 24.0);
  EXPECT_EQ(stated("comment export_fluid.py: Blender 3.6.0, object Liquid, frame 3, fps 29.97, velocity from "
                   "attribute\n"),
            29.97);
  EXPECT_EQ(stated("comment made by hand\ncomment FPS: 25\n"), 25.0);
  EXPECT_EQ(stated("obj_info fps=50\n"), 50.0);
  EXPECT_EQ(stated("comment fps=30000/1001\n"), 30000.0 / 1001.0);
  EXPECT_EQ(stated("comment fps=abc\ncomment then fps = 12\n"), 12.0);  // the first that states one
  for (const char* none : {"", "comment no rate here\n", "comment maxfps=60\n", "comment fps=0\n", "comment fps=-24\n",
                           "comment fps=24x\n", "comment fps 1.5.2\n", "comment fps\n", "comment fps=24/0\n",
                           "comment fps=24/\n", "comment fps=1/2/3\n"}) {
    EXPECT_EQ(stated(none), std::nullopt) << none;
  }
  // Not a PLY, or not a readable one: the frame's reading says why.
  write_file(dir.file("f.obj"), "# fps=24\nv 0 0 0\n");
  EXPECT_EQ(read_stated_fps(dir.file("f.obj")), std::nullopt);
  write_file(dir.file("bad.ply"), "ply\ncomment fps=24\n");  // no format, no end_header
  EXPECT_EQ(read_stated_fps(dir.file("bad.ply")), std::nullopt);
  EXPECT_EQ(read_stated_fps(dir.file("missing.ply")), std::nullopt);
  // Reading the frame takes no notice of the comment.
  EXPECT_EQ(read_frame(dir.file("f.ply")).num_faces(), 1u);
}

TEST(MeshClean, MergesDropsAndRenumbers) {
  FrameMesh m;
  // 0..3: a square split in two; 4 duplicates 2's position; 5 unreferenced;
  // 6 lies on segment 0-1 (zero-area triangle).
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, 1, 0}, {5, 5, 5}, {0.5, 0, 0}};
  m.velocities = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}, {9, 9, 9}, {6, 0, 0}};
  m.triangles = {{0, 1, 2}, {0, 4, 3},  // 4 merges into 2
                 {2, 0, 1},             // duplicate (rotated)
                 {0, 2, 1},             // duplicate (flipped)
                 {0, 0, 3},             // repeated index
                 {0, 6, 1}};            // zero area
  const CleanReport r = clean_mesh(m);
  EXPECT_EQ(r.merged_vertices, 1u);
  EXPECT_EQ(r.degenerate_faces, 2u);
  EXPECT_EQ(r.duplicate_faces, 2u);
  EXPECT_EQ(r.unreferenced_vertices, 2u);  // 5, and 6 once its triangle is gone
  ASSERT_EQ(m.num_vertices(), 4u);
  EXPECT_EQ(m.positions[3], Vec3(0, 1, 0));
  EXPECT_EQ(m.velocities[2], Vec3(3, 0, 0));  // mean of 2 and 4
  EXPECT_EQ(m.velocities[3], Vec3(3, 0, 0));
  ASSERT_EQ(m.num_faces(), 2u);
  EXPECT_EQ(m.triangles[1], (Tri{0, 2, 3}));
  EXPECT_EQ(r.boundary_edges, 4u);
  EXPECT_EQ(r.components, 1);
  EXPECT_EQ(r.summary(),
            "merged 1 vertex, dropped 2 degenerate and 2 duplicate faces, 2 unreferenced vertices; "
            "0 non-manifold edges, 4 boundary edges, 1 component");
}

TEST(MeshClean, ClosedMeshIsClean) {
  FrameMesh m;  // tetrahedron
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.velocities.assign(4, Vec3::Zero());
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  const CleanReport r = clean_mesh(m);
  EXPECT_EQ(r.summary(), "clean");
  EXPECT_EQ(m.num_faces(), 4u);
}

TEST(MeshClean, MergeToleranceIsRelativeToBoundingBox) {
  FrameMesh m;
  m.positions = {{0, 0, 0}, {100, 0, 0}, {0, 100, 0}, {100 + 1e-8, 1e-8, 0}, {100, 100, 0}};
  m.velocities = {{0, 0, 0}, {2, 0, 0}, {0, 0, 0}, {4, 0, 0}, {0, 0, 0}};
  m.triangles = {{0, 1, 2}, {3, 4, 2}};
  const CleanReport r = clean_mesh(m);
  EXPECT_EQ(r.merged_vertices, 1u);
  EXPECT_EQ(m.velocities[1], Vec3(3, 0, 0));
  EXPECT_EQ(r.components, 1);
}

TEST(MeshClean, NonManifoldEdgeIsCountedAndVelocitiesKept) {
  TempDir dir;
  // Three triangles on edge 0-1 (plus one more on a separate piece).
  const std::vector<Vec3> pos = {{0, 0, 0},   {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0},
                                 {0.5, 0, 1}, {5, 5, 5}, {6, 5, 5},   {5, 6, 5}};
  std::vector<Vec3> vel;
  for (int i = 0; i < 8; ++i) vel.emplace_back(i, 10 * i, -i);
  PlySpec spec;
  spec.format = "binary_big_endian";
  const std::string path = dir.file("fin.ply");
  write_file(path, make_ply(spec, pos, vel, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {5, 6, 7}}));
  CleanReport r;
  const FrameMesh m = read_frame(path, {}, &r);
  ASSERT_EQ(m.num_vertices(), 8u);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(m.velocities[i], vel[i]) << "vertex " << i;
  EXPECT_EQ(r.nonmanifold_edges, 1u);
  EXPECT_EQ(r.boundary_edges, 6u + 3u);
  EXPECT_EQ(r.components, 2);
  EXPECT_FALSE(r.changed());
}

TEST(MeshClean, ReadFrameMergesDuplicateVerticesFromFile) {
  TempDir dir;
  // Two triangles that share an edge only geometrically (vertices 2,3 = 4,5).
  const std::vector<Vec3> pos = {{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<Vec3> vel = {{0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {3, 0, 0}, {0, 4, 0}};
  const std::string path = dir.file("split.ply");
  write_file(path, make_ply({}, pos, vel, {{0, 2, 3}, {1, 5, 4}}));
  CleanReport r;
  const FrameMesh m = read_frame(path, {}, &r);
  EXPECT_EQ(r.merged_vertices, 2u);
  ASSERT_EQ(m.num_vertices(), 4u);
  EXPECT_EQ(m.velocities[2], Vec3(2, 0, 0));
  EXPECT_EQ(m.velocities[3], Vec3(0, 3, 0));
  EXPECT_EQ(r.boundary_edges, 4u);
  ReadOptions raw;
  raw.clean = false;
  EXPECT_EQ(read_frame(path, raw).num_vertices(), 6u);
}

// --- Real data -------------------------------------------------------------------------

TEST(RealData, ReadsTheBlenderDropSequence) {
  const std::filesystem::path dir = FLUIDTEX_SOURCE_DIR "/../shared/realdata/blender-drop";
  if (!std::filesystem::exists(dir / "drop.0001.ply")) GTEST_SKIP() << "no real data at " << dir;
  int frames = 0;
  double slowest_ms = 0.0;
  for (int frame = 1; frame <= 48; ++frame) {
    char name[32];
    std::snprintf(name, sizeof(name), "drop.%04d.ply", frame);
    const std::string path = (dir / name).string();
    if (!std::filesystem::exists(path)) continue;
    ++frames;
    const auto t0 = std::chrono::steady_clock::now();
    CleanReport report;
    const FrameMesh cleaned = read_frame(path, {}, &report);
    slowest_ms =
        std::max(slowest_ms, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    EXPECT_GT(cleaned.num_faces(), 0u) << name;
    if (frame % 16 != 1) continue;
    // Compare with a direct reading of the little-endian body: float x y z vx vy vz.
    ReadOptions raw;
    raw.clean = false;
    const FrameMesh m = read_frame(path, raw);
    const std::string bytes = test::read_file(path);
    const std::size_t body = bytes.find("end_header\n") + 11;
    const std::size_t nv = std::stoul(bytes.substr(bytes.find("element vertex ") + 15));
    ASSERT_EQ(m.num_vertices(), nv) << name;
    for (std::size_t i = 0; i < nv; i += 97) {
      float f[6];
      std::memcpy(f, bytes.data() + body + 24 * i, sizeof(f));
      for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(m.positions[i][a], f[a]) << name << " vertex " << i;
        EXPECT_EQ(m.velocities[i][a], f[3 + a]) << name << " vertex " << i;
      }
    }
    std::cout << name << ": " << m.num_vertices() << " vertices, " << m.num_faces() << " triangles; "
              << report.summary() << "\n";
  }
  std::cout << frames << " frames, slowest read_frame " << slowest_ms << " ms\n";
}

}  // namespace
}  // namespace fluidtex
