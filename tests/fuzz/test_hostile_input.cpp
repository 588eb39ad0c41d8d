// Hostile input, end to end: malformed meshes, images, paths, options and
// state files, generated here (nothing large is committed), each run through
// the fluidtex executable with a CPU, memory and wall-clock limit. For every
// case: no hang, no crash, exit code 0 or 2, an error is exactly one line on
// stderr naming the file when a file is at fault, no temporary file is left
// behind, every frame written is complete, and a second run gives the same
// exit code and message.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <sstream>
#include <thread>

#include "cli_server.h"
#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/job/job_options.h"
#include "fluidtex/scenes/exemplar_gen.h"
#include "fluidtex/scenes/scenes.h"
#include "test_util.h"

namespace fluidtex {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  int code = -1;  ///< exit code; -1: killed (signal or timeout)
  std::string out, err;
  bool timed_out = false;
};

#if defined(__SANITIZE_ADDRESS__)
/// Built with -fsanitize=address (FLUIDTEX_SANITIZE): ASan reserves terabytes
/// of address space for its shadow memory, so RLIMIT_AS would stop every run
/// at startup (CI caps memory with ASAN_OPTIONS=hard_rss_limit_mb instead),
/// and runs are several times slower.
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

/// Runs fluidtex with `args` under RLIMIT_AS (bytes), RLIMIT_CPU and a wall
/// clock limit, in `cwd`, in a process forked from the test binary's
/// command-line server (cli_server.h): the command line's entry point, the
/// same code without loading 270 shared libraries per run, or with
/// `executable` the executable itself.
Outcome run_limited(const std::vector<std::string>& args, const fs::path& cwd, double wall_seconds = 60.0,
                    rlim_t memory = 3ull << 30, bool executable = false) {
  const fs::path out_file = cwd / ".stdout", err_file = cwd / ".stderr";
  if (kSanitized) wall_seconds *= 5.0;
  const unsigned cpu_seconds = kSanitized ? 600u : 120u;
  Outcome r;
  int status = 0;
  const test::Command command =
      test::spawn_command_line(args, {cwd, out_file, err_file, executable ? fs::path(FLUIDTEX_EXE) : fs::path(),
                                      kSanitized ? 0 : static_cast<std::uint64_t>(memory), cpu_seconds});
  if (!test::wait_command_line(command, wall_seconds, status)) {
    ::kill(command.pid, SIGKILL);
    test::wait_command_line(command, 1e6, status);
    r.timed_out = true;
  }
  if (!r.timed_out && WIFEXITED(status)) r.code = WEXITSTATUS(status);
  r.out = test::read_file(out_file);
  r.err = test::read_file(err_file);
  fs::remove(out_file), fs::remove(err_file);
  return r;
}

// --- Generators --------------------------------------------------------------------------

const char* const kHeader =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "property float vx\nproperty float vy\nproperty float vz\nelement face 2\n"
    "property list uchar int vertex_indices\nend_header\n";
const char* const kVertices = "0 0 0 0 0 0\n1 0 0 0 0 0\n1 1 0 0 0 0\n0 1 0 0 0 0\n";
const char* const kFaces = "3 0 1 2\n3 0 2 3\n";

std::string ascii(const std::string& vertices = kVertices, const std::string& faces = kFaces,
                  const std::string& header = kHeader) {
  return header + vertices + faces;
}

/// kHeader with its first `from` replaced by `to`.
std::string header_with(const std::string& from, const std::string& to) {
  std::string h = kHeader;
  return h.replace(h.find(from), from.size(), to);
}

/// The same square as a binary little-endian PLY; `faces` is the raw face
/// body (count byte + int32 indices per face), `nf` its face count.
std::string binary(const std::string& faces, int nf, int nv = 4) {
  std::string h = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(nv) +
                  "\nproperty float x\nproperty float y\nproperty float z\nproperty float vx\nproperty float vy\n"
                  "property float vz\nelement face " +
                  std::to_string(nf) + "\nproperty list uchar int vertex_indices\nend_header\n";
  const float p[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int v = 0; v < 4; ++v) {
    const float row[6] = {p[v][0], p[v][1], 0, 0, 0, 0};
    h.append(reinterpret_cast<const char*>(row), sizeof row);
  }
  return h + faces;
}

std::string face_bytes(std::initializer_list<int> idx) {
  std::string s(1, static_cast<char>(idx.size()));
  for (int i : idx) s.append(reinterpret_cast<const char*>(&i), 4);
  return s;
}

/// A PNG whose header claims `w` x `h` pixels (the data is tiny).
std::string png_claiming(std::uint32_t w, std::uint32_t h) {
  auto be32 = [](std::uint32_t v) {
    return std::string{static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8),
                       static_cast<char>(v)};
  };
  std::string ihdr = be32(w) + be32(h) + std::string{8, 2, 0, 0, 0};
  auto chunk = [&](const std::string& type, const std::string& data) {
    return be32(static_cast<std::uint32_t>(data.size())) + type + data + be32(0);  // CRC not checked first
  };
  return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) + chunk("IDAT", std::string(16, '\0')) +
         chunk("IEND", "");
}

struct Case {
  std::string name;
  /// Prepares the case folder; returns the fluidtex arguments.
  std::function<std::vector<std::string>(const fs::path&)> setup;
  /// The file the message must name ("" = none).
  std::string names;
};

/// A run over a one-frame mesh `bytes` (m.0001.ply) with a good exemplar.
Case mesh_case(const std::string& name, const std::string& bytes) {
  return {name,
          [bytes](const fs::path& dir) {
            test::write_file(dir / "m.0001.ply", bytes);
            write_image((dir / "ex.png").string(), make_exemplar("gravel", 32, 1));
            // A radius near the square's size: few, small patches (a good
            // frame is 2 triangles, each patch a remeshed copy of them).
            return std::vector<std::string>{"run", "-q",  "-i",           "m.####.ply", "-e",       "ex.png",
                                            "-o",  "out", "--atlas-size", "64",         "--radius", "0.5"};
          },
          "m.0001.ply"};
}

/// A run over two copies of an OBJ frame (velocities from positions).
Case obj_case(const std::string& name, const std::string& bytes) {
  return {name,
          [bytes](const fs::path& dir) {
            test::write_file(dir / "m.0001.obj", bytes);
            test::write_file(dir / "m.0002.obj", bytes);
            write_image((dir / "ex.png").string(), make_exemplar("gravel", 32, 1));
            return std::vector<std::string>{"run", "-q",       "-i", "m.####.obj", "--velocity-from-positions",
                                            "-e",  "ex.png",   "-o", "out",        "--atlas-size",
                                            "64",  "--radius", "0.5"};
          },
          "m.0001.obj"};
}

/// A run over a small good sequence with extra arguments, after `prepare`.
Case scene_case(const std::string& name, std::vector<std::string> extra, const std::string& names = "",
                std::function<void(const fs::path&)> prepare = {}) {
  return {name,
          [extra, prepare](const fs::path& dir) {
            test::write_rotation_scene(dir, 3, 10);
            if (prepare) prepare(dir);
            std::vector<std::string> args{"run",    "-q", "-i",  "rotation.####.ply", "-e",
                                          "ex.png", "-o", "out", "--atlas-size",      "64"};
            args.insert(args.end(), extra.begin(), extra.end());
            return args;
          },
          names};
}

/// A run over a two-frame VDB sequence of the generated drop (level set
/// `surface`, velocity `vel`) with extra arguments, after `damage` changed
/// the bytes of frame 1.
Case vdb_case(const std::string& name, std::vector<std::string> extra,
              std::function<std::string(const std::string&)> damage, const std::string& names = "d.0001.vdb") {
  return {name,
          [extra, damage](const fs::path& dir) {
            SceneOptions scene;
            scene.frames = 2;
            scene.resolution = 10;
            scene.format = "vdb";
            write_scene("drop", dir.string(), scene);
            fs::rename(dir / "drop.0001.vdb", dir / "d.0001.vdb");
            fs::rename(dir / "drop.0002.vdb", dir / "d.0002.vdb");
            if (damage) test::write_file(dir / "d.0001.vdb", damage(test::read_file(dir / "d.0001.vdb")));
            write_image((dir / "ex.png").string(), make_exemplar("gravel", 32, 1));
            std::vector<std::string> args{"run",    "-q", "-i",  "d.####.vdb",   "-e",
                                          "ex.png", "-o", "out", "--atlas-size", "256"};
            args.insert(args.end(), extra.begin(), extra.end());
            return args;
          },
          names};
}

void add_vdb_cases(std::vector<Case>& c) {
  c.push_back(vdb_case("vdb_good", {}, {}, ""));
  c.push_back(vdb_case("vdb_text", {}, [](const std::string&) { return std::string("not a vdb\n"); }));
  c.push_back(vdb_case("vdb_empty", {}, [](const std::string&) { return std::string(); }));
  // Cut anywhere: in the header, in either grid's descriptor or data.
  for (int eighth = 1; eighth < 8; ++eighth) {
    c.push_back(vdb_case("vdb_cut_" + std::to_string(eighth) + "_of_8", {},
                         [eighth](const std::string& bytes) { return bytes.substr(0, bytes.size() * eighth / 8); }));
  }
  c.push_back(vdb_case("vdb_cut_in_header", {}, [](const std::string& bytes) { return bytes.substr(0, 60); }));
  c.push_back(vdb_case("vdb_no_such_surface", {"--vdb-surface", "phi"}, {}));
  c.push_back(vdb_case("vdb_no_such_velocity", {"--vdb-velocity", "flow"}, {}));
  c.push_back(vdb_case("vdb_surface_is_velocity", {"--vdb-surface", "vel"}, {}));
  c.push_back(vdb_case("vdb_velocity_is_surface", {"--vdb-velocity", "surface"}, {}));
  c.push_back(vdb_case("vdb_iso_misses_surface", {"--vdb-iso", "1e6"}, {}));
  c.push_back(vdb_case("vdb_adaptivity_out_of_range", {"--vdb-adaptivity", "2"}, {}, ""));
  c.push_back(vdb_case("velocity_vdb_missing", {"--velocity-vdb", "nowhere.####.vdb"}, {}, "nowhere.0001.vdb"));
}

/// The systematic part of the corpus: every field of an ASCII vertex line
/// with every bad token, binary files cut every 16 bytes and with single
/// bytes flipped, header variants, and every numeric or named option of
/// `run` with values of the wrong kind or out of range (the message must
/// name the option).
void add_generated_cases(std::vector<Case>& c) {
  for (int field = 0; field < 6; ++field) {
    for (const char* token : {"abc", "nan", "inf", "1e999", "", "0 0"}) {
      std::string line;
      for (int k = 0; k < 6; ++k) line += (k ? " " : "") + std::string(k == field ? token : "0");
      c.push_back(mesh_case("ascii_field_" + std::to_string(field) + "_" + (*token ? token : "missing"),
                            ascii(line + "\n1 0 0 0 0 0\n1 1 0 0 0 0\n0 1 0 0 0 0\n")));
    }
  }
  const std::string good = binary(face_bytes({0, 1, 2}) + face_bytes({0, 2, 3}), 2);
  const std::size_t body = good.find("end_header\n") + 11;
  for (std::size_t cut = 8; cut < good.size(); cut += 16)
    c.push_back(mesh_case("binary_cut_at_" + std::to_string(cut), good.substr(0, cut)));
  for (std::size_t at = body; at < good.size(); at += 9) {
    std::string flipped = good;
    flipped[at] = static_cast<char>(~flipped[at]);
    c.push_back(mesh_case("binary_flip_" + std::to_string(at), flipped));
  }
  const std::pair<const char*, const char*> headers[] = {
      {"format ascii 1.0", "format ascii 2.0"},
      {"format ascii 1.0", "format binary_big_endian 1.0"},
      {"format ascii 1.0", "format xml 1.0"},
      {"property float x", "property double x"},
      {"property float x", "property uchar x"},
      {"property float vz", "property list uchar float vz"},
      {"property list uchar int", "property list float int"},
      {"property list uchar int", "property list uchar float"},
      {"element face 2", "element face 1"},
      {"element face 2", "element face 3"},
      {"element vertex 4", "element vertex 3"},
      {"element vertex 4", "element vertex 5"},
      {"element vertex 4", "element vertex -4"},
      {"element face 2", "element edge 0\nelement face 2"},
      {"end_header", "comment x\nend_header"},
      {"ply\n", "ply \n"},
      {"property float y\n", ""},
      {"property float vx", "property float velocity_x"},
  };
  for (const auto& [from, to] : headers) {
    std::string name = std::string("header_") + to;
    c.push_back(mesh_case(name.substr(0, 40), ascii(kVertices, kFaces, header_with(from, to))));
  }
  // Options: every number and every named choice of the table, wrong.
  JobOptions defaults;
  for (const OptionRef& ref : option_table(defaults)) {
    const std::string name = ref.info.name, opt = "--" + name;
    std::vector<std::pair<std::string, std::string>> bad;  // (label, value)
    const std::string type = ref.type;
    if (type.rfind("FLOAT", 0) == 0)
      bad = {{"nan", "nan"}, {"overflow", "1e999"}, {"text", "abc"}, {"huge_negative", "-1e300"}};
    else if (type == "INT")
      bad = {{"text", "abc"}, {"overflow", "99999999999999999999"}, {"fraction", "1.5"}, {"negative", "-7"}};
    else if (!ref.choices.empty())
      bad = {{"unknown", "bogus"}};
    for (const auto& [label, value] : bad) {
      c.push_back(scene_case("option_" + name + "_" + label, {opt, value}, opt));
    }
  }
}

std::vector<Case> cases() {
  std::vector<Case> c;
  const std::string H = kHeader;
  // ASCII bodies: bad tokens, short and long lines, counts.
  for (const char* token : {"abc", "nan", "-nan", "inf", "-inf", "1e999", "1e39", "0x10", "1,5", "--1", "1e", "."}) {
    c.push_back(mesh_case(std::string("ascii_vertex_token_") + token,
                          ascii(std::string("0 0 0 ") + token + " 0 0\n1 0 0 0 0 0\n1 1 0 0 0 0\n0 1 0 0 0 0\n")));
  }
  for (const char* token : {"abc", "-1", "4", "99999999999", "2.5", "nan"})
    c.push_back(mesh_case(std::string("ascii_index_") + token,
                          ascii(kVertices, std::string("3 0 1 ") + token + "\n3 0 2 3\n")));
  for (const char* count : {"-3", "255", "300", "abc", "2.0", "0"})
    c.push_back(mesh_case(std::string("ascii_list_count_") + count,
                          ascii(kVertices, std::string(count) + " 0 1 2\n3 0 2 3\n")));
  c.push_back(mesh_case("ascii_vertex_short_line", ascii("0 0 0 0 0\n1 0 0 0 0 0\n1 1 0 0 0 0\n0 1 0 0 0 0\n")));
  c.push_back(mesh_case("ascii_vertex_long_line", ascii("0 0 0 0 0 0 7\n1 0 0 0 0 0\n1 1 0 0 0 0\n0 1 0 0 0 0\n")));
  c.push_back(mesh_case("ascii_two_vertices_one_line", ascii("0 0 0 0 0 0 1 0 0 0 0 0\n1 1 0 0 0 0\n0 1 0 0 0 0\n")));
  c.push_back(mesh_case("ascii_face_long_line", ascii(kVertices, "3 0 1 2 3\n3 0 2 3\n")));
  c.push_back(mesh_case("ascii_missing_face_line", ascii(kVertices, "3 0 1 2\n")));
  c.push_back(mesh_case("ascii_cut_mid_line", ascii(kVertices, "3 0 1 2\n3 0")));
  c.push_back(mesh_case("ascii_empty_body", H));
  c.push_back(mesh_case("ascii_crlf",
                        "ply\r\nformat ascii 1.0\r\nelement vertex 4\r\nproperty float x\r\n"
                        "property float y\r\nproperty float z\r\nproperty float vx\r\n"
                        "property float vy\r\nproperty float vz\r\nelement face 2\r\n"
                        "property list uchar int vertex_indices\r\nend_header\r\n0 0 0 0 0 0\r\n"
                        "1 0 0 0 0 0\r\n1 1 0 0 0 0\r\n0 1 0 0 0 0\r\n3 0 1 2\r\n3 0 2 3\r\n"));
  c.push_back(mesh_case("ascii_blank_lines", ascii("\n0 0 0 0 0 0\n\n1 0 0 0 0 0\n1 1 0 0 0 0\n0 1 0 0 0 0\n\n")));
  c.push_back(mesh_case("ascii_garbage_after_faces", ascii(kVertices, std::string(kFaces) + "garbage \x01\x02\n")));
  c.push_back(mesh_case("ascii_random_body", H + std::string("\x13\x88\xff\x00\x41 9 9 \xfe\n", 12)));
  c.push_back(mesh_case("ascii_short_faces_dropped",
                        ascii(kVertices, "0\n2 0 1\n3 0 1 2\n3 0 2 3\n", header_with("face 2", "face 4"))));
  c.push_back(mesh_case("ascii_one_far_vertex", ascii("0 0 0 0 0 0\n1 0 0 0 0 0\n1 1 0 0 0 0\n1e30 1 0 0 0 0\n")));
  // Headers.
  c.push_back(mesh_case("header_no_end", "ply\nformat ascii 1.0\nelement vertex 4\n"));
  {
    std::string no_end = ascii(kVertices, kFaces);
    no_end.erase(no_end.find("end_header\n"), 11);
    c.push_back(mesh_case("header_ascii_body_without_end_header", no_end));
  }
  c.push_back(mesh_case("header_nul", std::string("ply\nformat ascii 1.0\nelement vertex 4\0\0\0\n", 40) + kVertices));
  c.push_back(mesh_case("header_hex_count", ascii(kVertices, kFaces, header_with("vertex 4", "vertex 0x4"))));
  c.push_back(mesh_case("header_huge_count", ascii(kVertices, kFaces, header_with("vertex 4", "vertex 2147483647"))));
  c.push_back(
      mesh_case("header_too_large_count", ascii(kVertices, kFaces, header_with("vertex 4", "vertex 99999999999999"))));
  c.push_back(mesh_case("header_unknown_type", ascii(kVertices, kFaces, header_with("float vx", "quad vx"))));
  c.push_back(mesh_case("header_no_velocity",
                        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                        "property float y\nproperty float z\nelement face 1\n"
                        "property list uchar int vertex_indices\nend_header\n"
                        "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
  c.push_back(mesh_case("header_bad_magic", "plx\n" + ascii().substr(4)));
  c.push_back(mesh_case("header_only_magic", "ply\n"));
  c.push_back(mesh_case("empty_file", ""));
  // Polygons.
  {
    std::string h =
        "ply\nformat ascii 1.0\nelement vertex 300\nproperty float x\nproperty float y\n"
        "property float z\nproperty float vx\nproperty float vy\nproperty float vz\n"
        "element face 1\nproperty list ushort int vertex_indices\nend_header\n";
    std::ostringstream body;
    for (int k = 0; k < 300; ++k)
      body << std::cos(2 * M_PI * k / 300) << " " << std::sin(2 * M_PI * k / 300) << " 0 0 0 0\n";
    body << 300;
    for (int k = 0; k < 300; ++k) body << " " << k;
    body << "\n";
    c.push_back(mesh_case("polygon_300_corners", h + body.str()));
  }
  // Binary bodies.
  c.push_back(mesh_case("binary_good", binary(face_bytes({0, 1, 2}) + face_bytes({0, 2, 3}), 2)));
  c.push_back(mesh_case("binary_truncated", binary(face_bytes({0, 1, 2}) + face_bytes({0, 2}), 2)));
  c.push_back(
      mesh_case("binary_short_face_kept", binary(face_bytes({}) + face_bytes({0, 1, 2}) + face_bytes({0, 2, 3}), 3)));
  c.push_back(mesh_case("binary_huge_list", binary(std::string(1, '\xff') + face_bytes({0, 2, 3}), 2)));
  c.push_back(mesh_case("binary_index_out_of_range", binary(face_bytes({0, 1, 7}) + face_bytes({0, 2, 3}), 2)));
  c.push_back(mesh_case("binary_nan_position", [] {
    std::string b = binary(face_bytes({0, 1, 2}) + face_bytes({0, 2, 3}), 2);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    b.replace(b.find("end_header\n") + 11, 4, reinterpret_cast<const char*>(&nan), 4);
    return b;
  }()));
  c.push_back(mesh_case("binary_random_body", binary(std::string("\x03\x10\x27\x00\x00\xff\xff\xff\x7f", 9), 2)));
  // OBJ frames.
  const std::string quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";
  c.push_back(obj_case("obj_good", quad + "f 1 2 3\nf 1 3 4\n"));
  c.push_back(obj_case("obj_short_vertex", "v 0 0 0\nv 1 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n"));
  c.push_back(obj_case("obj_bad_token", "v 0 0 0\nv 1 abc 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n"));
  c.push_back(obj_case("obj_nan", "v 0 0 0\nv nan 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n"));
  c.push_back(obj_case("obj_overflow", "v 0 0 0\nv 1e999 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n"));
  c.push_back(obj_case("obj_index_out_of_range", quad + "f 1 2 99\nf 1 3 4\n"));
  c.push_back(obj_case("obj_negative_index", quad + "f 1 2 -9\nf 1 3 4\n"));
  c.push_back(obj_case("obj_no_faces", quad));
  c.push_back(obj_case("obj_binary", std::string("v 0 0 0\n\0\x01\x02", 11)));
  // Paths that are not regular files.
  auto replace_frame = [](const std::function<void(const fs::path&)>& make) {
    return [make](const fs::path& dir) {
      fs::remove(dir / "rotation.0002.ply");
      make(dir / "rotation.0002.ply");
    };
  };
  c.push_back(scene_case("frame_is_folder", {}, "rotation.0002.ply",
                         replace_frame([](const fs::path& p) { fs::create_directory(p); })));
  c.push_back(scene_case("frame_is_fifo", {}, "rotation.0002.ply",
                         replace_frame([](const fs::path& p) { ::mkfifo(p.c_str(), 0644); })));
  c.push_back(scene_case("frame_dangling_link", {}, "rotation.0002.ply",
                         replace_frame([](const fs::path& p) { fs::create_symlink("nowhere.ply", p); })));
  c.push_back(scene_case("frame_link_loop", {}, "rotation.0002.ply",
                         replace_frame([](const fs::path& p) { fs::create_symlink(p.filename(), p); })));
  c.push_back(scene_case("frame_missing_in_range", {"--frames", "1-5"}, "rotation.0004.ply"));
  // Exemplars.
  auto exemplar = [](const std::function<void(const fs::path&)>& make) {
    return [make](const fs::path& dir) {
      fs::remove(dir / "ex.png");
      make(dir / "ex.png");
    };
  };
  c.push_back(scene_case("exemplar_missing", {}, "ex.png", exemplar([](const fs::path&) {})));
  c.push_back(
      scene_case("exemplar_folder", {}, "ex.png", exemplar([](const fs::path& p) { fs::create_directory(p); })));
  c.push_back(
      scene_case("exemplar_fifo", {}, "ex.png", exemplar([](const fs::path& p) { ::mkfifo(p.c_str(), 0644); })));
  c.push_back(scene_case("exemplar_dev_zero", {}, "ex.png",
                         exemplar([](const fs::path& p) { fs::create_symlink("/dev/zero", p); })));
  c.push_back(scene_case("exemplar_text", {}, "ex.png",
                         exemplar([](const fs::path& p) { test::write_file(p, "not an image\n"); })));
  c.push_back(scene_case("exemplar_claims_65535", {}, "ex.png",
                         exemplar([](const fs::path& p) { test::write_file(p, png_claiming(65535, 65535)); })));
  c.push_back(scene_case("exemplar_claims_16384", {}, "ex.png",
                         exemplar([](const fs::path& p) { test::write_file(p, png_claiming(16384, 16384)); })));
  c.push_back(scene_case("exemplar_truncated", {}, "ex.png", exemplar([](const fs::path& p) {
                           write_image(p.string(), make_exemplar("gravel", 64, 2));
                           const std::string bytes = test::read_file(p);
                           test::write_file(p, bytes.substr(0, bytes.size() / 2));
                         })));
  // Options and patterns.
  c.push_back(scene_case("frames_two_billion", {"--frames", "1-2000000000"}));
  c.push_back(scene_case("frames_malformed", {"--frames", "1-x"}));
  c.push_back({"pattern_width_huge",
               [](const fs::path&) {
                 return std::vector<std::string>{"run", "-q", "-i", "m.%99999999999d.ply", "-e", "ex.png", "-o", "o"};
               },
               "m.%99999999999d.ply"});
  c.push_back(scene_case("radius_tiny", {"--radius", "1e-6"}));
  c.push_back(scene_case("radius_negative", {"--radius", "-1"}));
  c.push_back(scene_case("radius_text", {"--radius", "big"}));
  c.push_back(scene_case("uv_scale_huge", {"--uv-scale", "1e300"}));
  c.push_back(scene_case("atlas_too_small", {"--atlas-size", "16", "--gutter", "64"}));
  c.push_back(scene_case("unknown_option", {"--bogus"}));
  c.push_back(scene_case("config_missing", {"--config", "nowhere.toml"}, "nowhere.toml"));
  c.push_back(scene_case("config_garbage", {"--config", "c.toml"}, "c.toml",
                         [](const fs::path& dir) { test::write_file(dir / "c.toml", "radius = = 3\n[[[\n\x01\x02"); }));
  c.push_back(scene_case("config_bad_value", {"--config", "c.toml"}, "c.toml",
                         [](const fs::path& dir) { test::write_file(dir / "c.toml", "fade-frames = 0\n"); }));
  // State files under --resume: a job of frame 1 is made, then its state replaced.
  auto state = [](const std::string& bytes) {
    return [bytes](const fs::path& dir) {
      const std::string d = dir.string();
      EXPECT_EQ(test::run_fluidtex("run -q -i '" + d + "/rotation.####.ply' -e '" + d + "/ex.png' -o '" + d +
                                   "/out' --atlas-size 64 --frames 1"),
                0);
      test::write_file(dir / "out" / "state" / "patches.0001.bin", bytes);
    };
  };
  c.push_back(scene_case("state_garbage", {"--resume"}, "patches.0001.bin", state("FTXSTATE\x02\0\0\0garbage")));
  c.push_back(scene_case("state_empty", {"--resume"}, "patches.0001.bin", state("")));
  c.push_back(scene_case("state_bad_stream", {"--resume"}, "patches.0001.bin",
                         state(std::string("FTXSTATE\x03\0\0\0", 12) + std::string(8, '\0') + "\x10" +
                               std::string(7, '\0') + "\x20" + std::string(7, '\0') + "blosc?garbage")));
  add_generated_cases(c);
  add_vdb_cases(c);
  c.push_back(scene_case("stale_temporaries_removed", {}, "", [](const fs::path& dir) {
    fs::create_directories(dir / "out");
    test::write_file(dir / "out" / ".atlas.0001.tmp-999999999-3.exr", "half");
  }));
  return c;
}

/// Every file under `dir` whose name marks an unfinished atomic write.
std::vector<std::string> temporaries(const fs::path& dir) {
  std::vector<std::string> found;
  std::error_code ec;
  if (!fs::exists(dir, ec)) return found;
  for (const auto& e : fs::recursive_directory_iterator(dir, ec)) {
    if (e.path().filename().string().find(".tmp-") != std::string::npos) found.push_back(e.path().string());
  }
  return found;
}

/// Frames with an atlas but no mesh or state (or the other way round).
std::vector<int> partial_frames(const fs::path& out) {
  std::vector<int> partial;
  for (int f = 1; f <= 5; ++f) {
    const bool atlas = fs::exists(out / FramePattern("atlas.####.exr").path(f));
    const bool mesh = fs::exists(out / FramePattern("mesh.####.obj").path(f));
    const bool material = fs::exists(out / FramePattern("mesh.####.mtl").path(f));
    const bool state = fs::exists(out / "state" / FramePattern("patches.####.bin").path(f));
    if (atlas != mesh || mesh != material || (atlas && !state)) partial.push_back(f);
  }
  return partial;
}

class HostileInput : public ::testing::TestWithParam<std::size_t> {};

TEST_P(HostileInput, ExitsCleanlyWithOneLine) {
  const Case c = cases()[GetParam()];
  SCOPED_TRACE(c.name);
  test::TempDir root;
  const fs::path dir = root.path() / "first";
  fs::create_directories(dir);
  const Outcome first = run_limited(c.setup(dir), dir);
  ASSERT_FALSE(first.timed_out) << "hang";
  ASSERT_TRUE(first.code == 0 || first.code == 2) << "exit " << first.code << ": " << first.err;
  if (first.code == 2) {
    ASSERT_FALSE(first.err.empty());
    EXPECT_EQ(first.err.find('\n'), first.err.size() - 1) << "not one line: " << first.err;
    EXPECT_EQ(first.err.rfind("fluidtex: error: ", 0), 0u) << first.err;
    if (!c.names.empty()) EXPECT_NE(first.err.find(c.names), std::string::npos) << first.err;
  }
  EXPECT_EQ(temporaries(dir), std::vector<std::string>{});
  EXPECT_EQ(partial_frames(dir / "out"), std::vector<int>{});
  // The same again, in a fresh folder.
  const fs::path again = root.path() / "second";
  fs::create_directories(again);
  const Outcome second = run_limited(c.setup(again), again);
  EXPECT_EQ(second.code, first.code);
  EXPECT_EQ(second.err, first.err);
}

std::string case_name(const ::testing::TestParamInfo<std::size_t>& info) {
  std::string name = cases()[info.param].name;
  for (char& ch : name) {
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  }
  return name + "_" + std::to_string(info.param);
}

INSTANTIATE_TEST_SUITE_P(Cases, HostileInput, ::testing::Range<std::size_t>(0, cases().size()), case_name);

/// A job too big for the memory it is given ends with one line and exit 2
/// (std::bad_alloc was "internal error", exit 1).
TEST(OutOfMemory, IsOneLineAndExit2) {
  if (kSanitized) GTEST_SKIP() << "ASan replaces the allocator's failure with its own report";
  test::TempDir dir;
  test::write_rotation_scene(dir.path(), 2, 10);
  const Outcome r = run_limited(
      {"run", "-q", "-i", "rotation.####.ply", "-e", "ex.png", "-o", "out", "--atlas-size", "32768", "--threads", "1"},
      dir.path(), 60.0, 1ull << 30, true);
  ASSERT_FALSE(r.timed_out);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(r.err, "fluidtex: error: out of memory: lower --atlas-size or --threads, or give the job more memory\n");
  EXPECT_EQ(temporaries(dir.path()), std::vector<std::string>{});
  EXPECT_EQ(partial_frames(dir.path() / "out"), std::vector<int>{});
}

/// kill -9 at several moments of a run, then --resume: the outputs are
/// byte-identical to an uninterrupted run, and nothing temporary is left.
TEST(KillAndResume, GivesTheUninterruptedOutputs) {
  test::TempDir dir;
  const int frames = 6;
  test::write_rotation_scene(dir.path(), frames, 16);
  auto args = [&](const std::string& out) {
    return std::vector<std::string>{
        "run", "-q", "-i", "rotation.####.ply", "-e", "ex.png", "-o", out, "--atlas-size", "128", "--seed", "3"};
  };
  const auto start = std::chrono::steady_clock::now();
  ASSERT_EQ(run_limited(args("full"), dir.path()).code, 0);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  int interrupted = 0;
  for (const double at : {0.1, 0.35, 0.6, 0.85}) {
    const std::string out = "killed" + std::to_string(static_cast<int>(at * 100));
    SCOPED_TRACE(out);
    interrupted += run_limited(args(out), dir.path(), at * seconds).timed_out;  // or it finished first
    std::vector<std::string> resume = args(out);
    resume.push_back("--resume");
    const Outcome resumed = run_limited(resume, dir.path());
    ASSERT_EQ(resumed.code, 0) << resumed.err;
    EXPECT_EQ(temporaries(dir.path() / out), std::vector<std::string>{});
    for (int f = 1; f <= frames; ++f) {
      for (const std::string pattern : {"atlas.####.exr", "mesh.####.obj", "state/patches.####.bin"}) {
        const std::string name = FramePattern(pattern).path(f);
        EXPECT_EQ(test::read_file(dir.path() / "full" / name), test::read_file(dir.path() / out / name)) << name;
      }
    }
  }
  EXPECT_GE(interrupted, 2);  // the test kills runs mid-way
}

/// kill -9 a farm's synthesis step at several moments (with --prune-state, so
/// a kill may land while it prunes), then run it again unchanged: the
/// atlases and meshes are those of one uninterrupted run.
TEST(KillAndRerun, ASynthStepFinishesTheSame) {
  test::TempDir dir;
  const int frames = 6;
  test::write_rotation_scene(dir.path(), frames, 16);
  auto run = [&](const std::string& out, const std::string& extra) {
    std::vector<std::string> a{"run", "-q",     "-i", "rotation.####.ply", "-e", "ex.png", "-o", out, "--atlas-size",
                               "128", "--seed", "3"};
    if (!extra.empty()) a.push_back(extra);
    return a;
  };
  ASSERT_EQ(run_limited(run("full", ""), dir.path()).code, 0);
  // One tracked job, copied for each kill; one uninterrupted synth step
  // tells how long a step takes.
  ASSERT_EQ(run_limited(run("tracked", "--track-only"), dir.path()).code, 0);
  fs::copy(dir.path() / "tracked", dir.path() / "timed", fs::copy_options::recursive);
  const auto synth = [](const std::string& out) {
    return std::vector<std::string>{"synth", "-q", "-o", out, "--prune-state"};
  };
  const auto start = std::chrono::steady_clock::now();
  ASSERT_EQ(run_limited(synth("timed"), dir.path()).code, 0);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  int interrupted = 0;
  for (const double at : {0.15, 0.4, 0.65, 0.9}) {
    const std::string out = "farm" + std::to_string(static_cast<int>(at * 100));
    SCOPED_TRACE(out);
    fs::copy(dir.path() / "tracked", dir.path() / out, fs::copy_options::recursive);
    interrupted += run_limited(synth(out), dir.path(), at * seconds).timed_out;
    const Outcome again = run_limited(synth(out), dir.path());
    ASSERT_EQ(again.code, 0) << again.err;
    EXPECT_EQ(temporaries(dir.path() / out), std::vector<std::string>{});
    for (int f = 1; f <= frames; ++f) {
      for (const std::string pattern : {"atlas.####.exr", "mesh.####.obj"}) {
        const std::string name = FramePattern(pattern).path(f);
        EXPECT_EQ(test::read_file(dir.path() / "full" / name), test::read_file(dir.path() / out / name)) << name;
      }
    }
    EXPECT_EQ(test::list_dir(dir.path() / out / "state"), std::vector<std::string>{"patches.0006.bin"});
  }
  EXPECT_GE(interrupted, 2);  // the test kills steps mid-way
}

/// A radius far below the input's triangles: the patches would need more
/// memory than the run may use. Refused before tracking, naming --radius
/// with the estimate (it grew for minutes and then blamed --atlas-size).
/// Out of memory elsewhere names the option that sizes that command's
/// buffers (preview: --width).
TEST(OutOfMemory, TheOptionThatDrivesTheMemoryIsNamed) {
  if (kSanitized) GTEST_SKIP() << "ASan replaces the allocator's failure with its own report";
  test::TempDir dir;
  test::write_rotation_scene(dir.path(), 2, 16);
  const Outcome r = run_limited({"run", "-q", "-i", "rotation.####.ply", "-e", "ex.png", "-o", "out", "--frames", "1-2",
                                 "--radius", "0.01", "--atlas-size", "128", "--threads", "1"},
                                dir.path(), 30.0, 2ull << 30, true);
  ASSERT_FALSE(r.timed_out);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(
      r.err.find("--radius 0.01 gives about 9971 Poisson disks on the first frame, whose patches need about 10.8 GB "),
      std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find(" GB): raise --radius\n"), std::string::npos) << r.err;  // the limit: 2.1 GB or less
  // Nothing is left: the corrected command runs without --force.
  EXPECT_EQ(test::list_dir(dir.path() / "out"), std::vector<std::string>{});
  ASSERT_EQ(run_limited({"run", "-q", "-i", "rotation.####.ply", "-e", "ex.png", "-o", "out", "--atlas-size", "64"},
                        dir.path())
                .code,
            0);
  const Outcome p = run_limited({"preview", "out", "--width", "16384"}, dir.path(), 60.0, 1ull << 30, true);
  EXPECT_EQ(p.code, 2) << p.err;
  EXPECT_EQ(p.err, "fluidtex: error: out of memory: lower --width, or give the job more memory\n");
}

/// Exit 2 with one line naming `names`.
void expect_refused(const Outcome& o, const std::string& names) {
  EXPECT_EQ(o.code, 2) << o.err;
  EXPECT_EQ(o.err.find('\n'), o.err.size() - 1) << "not one line: " << o.err;
  EXPECT_NE(o.err.find(names), std::string::npos) << o.err;
}

/// The farm workflow's silent failures: a state of another job or another
/// frame, or a job.toml edited after tracking, is refused naming the cause;
/// a job with a hole resumes into the uninterrupted outputs.
TEST(JobIntegrity, AStateThatIsNotTheJobsIsRefusedAndHolesAreMadeAgain) {
  test::TempDir dir;
  test::write_rotation_scene(dir.path(), 6, 16);
  const std::vector<std::string> base{"run",    "-q",           "-i",  "rotation.####.ply", "-e",
                                      "ex.png", "--atlas-size", "128", "--threads",         "1"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = base;
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  ASSERT_EQ(run_limited(with({"-o", "a", "--track-only", "--seed", "3"}), dir.path()).code, 0);
  ASSERT_EQ(run_limited(with({"-o", "b", "--track-only", "--seed", "9"}), dir.path()).code, 0);
  const fs::path state2 = dir.path() / "a/state/patches.0002.bin";
  const std::string own = test::read_file(state2);
  const std::vector<std::string> synth{"synth", "-q", "-o", "a", "--frames", "2"};
  // Another job's state of the same frame.
  fs::copy_file(dir.path() / "b/state/patches.0002.bin", state2, fs::copy_options::overwrite_existing);
  expect_refused(run_limited(synth, dir.path()), "--seed is '3' in the job, but this state was tracked with '9'");
  // The job's own state of another frame (the mesh is the same on both).
  fs::copy_file(dir.path() / "a/state/patches.0003.bin", state2, fs::copy_options::overwrite_existing);
  expect_refused(run_limited(synth, dir.path()), "the state of frame 3, not of frame 2");
  test::write_file(state2, own);
  // A method option edited in job.toml after tracking.
  const fs::path toml = dir.path() / "a/job.toml";
  const std::string job = test::read_file(toml);
  std::string edited = job;
  const std::size_t at = edited.find("uv-scale=1\n");
  ASSERT_NE(at, std::string::npos) << job;
  edited.replace(at, 11, "uv-scale=2\n");
  test::write_file(toml, edited);
  expect_refused(run_limited(synth, dir.path()), "--uv-scale is '2' in the job, but this state was tracked with '1'");
  test::write_file(toml, job);
  EXPECT_FALSE(fs::exists(dir.path() / "a/atlas.0002.exr"));
  ASSERT_EQ(run_limited(synth, dir.path()).code, 0);
  // A hole in a finished job: --resume makes the frame again, as it was.
  ASSERT_EQ(run_limited(with({"-o", "r", "--seed", "3"}), dir.path()).code, 0);
  const std::string atlas3 = test::read_file(dir.path() / "r/atlas.0003.exr");
  for (const char* lost : {"r/atlas.0003.exr", "r/mesh.0003.obj", "r/mesh.0003.mtl", "r/state/patches.0003.bin"})
    fs::remove(dir.path() / lost);
  const Outcome resumed = run_limited(with({"-o", "r", "--seed", "3", "--resume"}), dir.path());
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  EXPECT_EQ(test::read_file(dir.path() / "r/atlas.0003.exr"), atlas3);
  EXPECT_TRUE(fs::exists(dir.path() / "r/state/patches.0003.bin"));
  // The farm harness's other cases: one output path for two outputs, a
  // --config that is not a file, NaN and out-of-range numbers.
  expect_refused(
      run_limited(with({"-o", "x", "--atlas", "x/a.####.exr", "--displacement-atlas", "x/a.####.exr"}), dir.path()),
      "would write the same file");
  expect_refused(run_limited(with({"-o", "x", "--config", "."}), dir.path()), "config file is a folder");
  expect_refused(run_limited(with({"-o", "x", "--config", "/dev/zero"}), dir.path()),
                 "config file is a character device");
  expect_refused(run_limited({"compare", "r", "r", "--mean-tolerance", "nan"}, dir.path()), "--mean-tolerance");
  expect_refused(run_limited({"compare", "r", "r", "--percentile", "nan"}, dir.path()), "--percentile");
  expect_refused(run_limited({"preview", "r", "--velocity-scale", "nan"}, dir.path()), "--velocity-scale");
  expect_refused(run_limited({"eval", "-o", "r", "--flow-max-motion", "nan"}, dir.path()), "--flow-max-motion");
  expect_refused(run_limited({"eval", "-o", "r", "--images", "-1"}, dir.path()), "--images");
}

}  // namespace
}  // namespace fluidtex
