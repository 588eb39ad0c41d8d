// PLY header checks for the readers of io/ (private to them: mesh_io.cpp's
// frames, uv_mesh_io.cpp's UV meshes): parse the header, decide
// which properties hold positions and velocities, measure binary bodies, and
// write the canonical header OpenMesh's PLYReader is given. OpenMesh parses
// the header too, but reports nothing usable (it prints to omerr and returns
// false), so every check whose failure the user must understand is done here.
#pragma once

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "fluidtex/util/error.h"

namespace fluidtex::plyio {

/// What an empty frame's error adds: solvers write frames without liquid.
inline constexpr const char* kNoLiquidHint = "; a frame without liquid: leave it out of --frames";

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;  ///< value type (list entries for lists)
  bool is_list = false;
  PlyType count_type = PlyType::UInt8;  ///< lists only
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
  int find(const std::string& prop) const {
    for (std::size_t i = 0; i < properties.size(); ++i)
      if (properties[i].name == prop) return static_cast<int>(i);
    return -1;
  }
};

enum class PlyFormat { Ascii, BinaryLE, BinaryBE };

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  std::vector<std::string> comments;  ///< text of the comment and obj_info lines, in order
  std::size_t body_offset = 0;        ///< first byte after the end_header line
};

/// Where the data OpenMesh must deliver lives, by element and property index.
struct PlyLayout {
  std::size_t vertex_element = 0, face_element = 0;
  std::array<int, 3> position_prop{};
  std::array<PlyType, 3> position_type{};
  bool has_velocity = false;
  std::array<int, 3> velocity_prop{-1, -1, -1};
  std::array<PlyType, 3> velocity_type{};
  std::size_t body_end = 0;  ///< first byte after the faces: OpenMesh reads no further
};

inline const char* type_name(PlyType t) {
  static const char* names[] = {"char", "uchar", "short", "ushort", "int", "uint", "float", "double"};
  return names[static_cast<int>(t)];
}

inline int type_size(PlyType t) {
  static const int sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
  return sizes[static_cast<int>(t)];
}

inline bool is_float(PlyType t) { return t == PlyType::Float32 || t == PlyType::Float64; }

inline bool parse_type(const std::string& s, PlyType& t) {
  static const std::pair<const char*, PlyType> table[] = {
      {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
      {"uint8", PlyType::UInt8},    {"short", PlyType::Int16},     {"int16", PlyType::Int16},
      {"ushort", PlyType::UInt16},  {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
      {"int32", PlyType::Int32},    {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
      {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64},
      {"float64", PlyType::Float64}};
  for (const auto& [name, type] : table)
    if (s == name) return t = type, true;
  return false;
}

inline std::string canonical_position_name(int axis) { return "fluidtex_p" + std::to_string(axis); }
inline std::string canonical_velocity_name(int axis) { return "fluidtex_v" + std::to_string(axis); }

/// An `element <name> <count>` line's element (`bad(why)` makes the error).
template <class Bad>
PlyElement parse_ply_element(const std::vector<std::string>& tok, const Bad& bad) {
  unsigned long long count = 0;
  const auto parsed = tok.size() == 3 ? std::from_chars(tok[2].data(), tok[2].data() + tok[2].size(), count)
                                      : std::from_chars_result{nullptr, std::errc::invalid_argument};
  if (parsed.ec != std::errc() || parsed.ptr != tok[2].data() + tok[2].size())
    throw bad("expected 'element <name> <count>' with a decimal count");
  if (count > 0x7fffffffull) throw bad("element count " + tok[2] + " is too large");
  return {tok[1], static_cast<std::size_t>(count), {}};
}

/// A `property <type> <name>` or `property list <count type> <type> <name>`
/// line's property (`bad(why)` makes the error).
template <class Bad>
PlyProperty parse_ply_property(const std::vector<std::string>& tok, const Bad& bad) {
  PlyProperty p;
  const bool list = tok.size() == 5 && tok[1] == "list";
  if (!list && tok.size() != 3) throw bad("expected 'property <type> <name>' or 'property list ...'");
  const std::string& value_type = list ? tok[3] : tok[1];
  if (list && !parse_type(tok[2], p.count_type)) throw bad("unknown list count type '" + tok[2] + "'");
  if (!parse_type(value_type, p.type)) throw bad("unknown property type '" + value_type + "'");
  if (list && is_float(p.count_type)) throw bad("list count type must be an integer type");
  p.is_list = list;
  p.name = tok.back();
  return p;
}

/// Parses the header; throws InputError for bad magic, an unsupported format,
/// unknown types or keywords, or a header without end_header.
inline PlyHeader parse_ply_header(const std::string& path, const std::string& bytes) {
  if (bytes.compare(0, 4, "ply\n") != 0 && bytes.compare(0, 5, "ply\r\n") != 0)
    throw InputError(path, "not a PLY file (bad magic: the file must start with 'ply')");
  PlyHeader h;
  bool have_format = false;
  std::size_t pos = bytes.find('\n') + 1;
  for (int line_no = 2;; ++line_no) {
    if (pos >= bytes.size()) throw InputError(path, "truncated PLY header (no end_header line)");
    std::size_t eol = bytes.find('\n', pos);
    const std::size_t next = eol == std::string::npos ? bytes.size() : eol + 1;
    if (eol == std::string::npos) eol = bytes.size();
    const std::string text = bytes.substr(pos, eol - pos);
    if (text.find('\0') != std::string::npos)
      throw InputError(path, "malformed PLY header line " + std::to_string(line_no) +
                                 ": binary data before end_header (is the end_header line missing?)");
    std::istringstream line(text);
    pos = next;
    std::vector<std::string> tok;
    for (std::string t; line >> t;) tok.push_back(t);
    auto bad = [&](const std::string& why) {
      return InputError(path, "malformed PLY header line " + std::to_string(line_no) + ": " + why);
    };
    if (!tok.empty() && (tok[0] == "comment" || tok[0] == "obj_info")) {
      const std::size_t start = text.find(tok[0]) + tok[0].size();
      h.comments.push_back(text.substr(std::min(text.size(), start + 1)));
      continue;
    }
    if (tok.empty()) continue;
    if (tok[0] == "end_header") break;
    if (tok[0] == "format") {
      if (tok.size() < 2) throw bad("format line without a format");
      if (tok[1] == "ascii")
        h.format = PlyFormat::Ascii;
      else if (tok[1] == "binary_little_endian")
        h.format = PlyFormat::BinaryLE;
      else if (tok[1] == "binary_big_endian")
        h.format = PlyFormat::BinaryBE;
      else
        throw InputError(path, "unsupported PLY format '" + tok[1] + "'");
      have_format = true;
    } else if (tok[0] == "element") {
      h.elements.push_back(parse_ply_element(tok, bad));
    } else if (tok[0] == "property") {
      if (h.elements.empty()) throw bad("property before any element");
      h.elements.back().properties.push_back(parse_ply_property(tok, bad));
    } else if (std::strtod(tok[0].c_str(), nullptr) != 0.0 || tok[0].find_first_not_of("+-.0") == std::string::npos) {
      // A number where a keyword goes: the body of an ASCII file.
      throw bad("numbers before end_header (is the end_header line missing?)");
    } else if (std::any_of(tok[0].begin(), tok[0].end(),
                           [](char c) { return !std::isprint(static_cast<unsigned char>(c)); })) {
      throw bad("binary data before end_header (is the end_header line missing?)");
    } else {
      throw bad("unknown keyword '" + tok[0].substr(0, 40) + "'");
    }
  }
  if (!have_format) throw InputError(path, "malformed PLY header: no format line");
  h.body_offset = pos;
  return h;
}

/// The frame rate a header comment states, as exporters write it: "fps=24",
/// "fps 24", "fps: 23.976", "fps=30000/1001" (any case; the first statement
/// of a positive, finite rate wins). nullopt when no comment states one.
inline std::optional<double> stated_fps(const std::vector<std::string>& comments) {
  const auto word_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  for (const std::string& comment : comments) {
    std::string lower = comment;
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    for (std::size_t at = lower.find("fps"); at != std::string::npos; at = lower.find("fps", at + 1)) {
      if (at > 0 && word_char(lower[at - 1])) continue;
      std::size_t i = at + 3;
      while (i < lower.size() && lower[i] == ' ') ++i;
      if (i < lower.size() && (lower[i] == '=' || lower[i] == ':')) ++i;
      while (i < lower.size() && lower[i] == ' ') ++i;
      const char* const stop = lower.data() + lower.size();
      double fps = 0.0;
      auto [end, ec] = std::from_chars(lower.data() + i, stop, fps);
      if (ec != std::errc() || end == lower.data() + i) continue;
      if (end != stop && *end == '/') {  // a rational rate: 30000/1001
        double denominator = 0.0;
        const auto [den_end, den_ec] = std::from_chars(end + 1, stop, denominator);
        if (den_ec != std::errc() || den_end == end + 1 || !(denominator > 0.0)) continue;
        fps /= denominator;
        end = den_end;
      }
      if (end != stop && (word_char(*end) || *end == '.' || *end == '/')) continue;
      if (std::isfinite(fps) && fps > 0.0) return fps;
    }
  }
  return std::nullopt;
}

/// Reads one list count at `at` of a binary body (the caller checked bounds).
inline long long read_count(const std::string& bytes, std::size_t at, PlyType t, bool big_endian) {
  unsigned char b[4] = {0, 0, 0, 0};
  const int n = type_size(t);
  for (int i = 0; i < n; ++i) b[i] = static_cast<unsigned char>(bytes[at + (big_endian ? n - 1 - i : i)]);
  const unsigned long long u = b[0] | (b[1] << 8) | (b[2] << 16) | (static_cast<unsigned long long>(b[3]) << 24);
  switch (t) {
    case PlyType::Int8: return static_cast<std::int8_t>(u);
    case PlyType::Int16: return static_cast<std::int16_t>(u);
    case PlyType::Int32: return static_cast<std::int32_t>(u);
    default: return static_cast<long long>(u);
  }
}

/// Walks a binary body up to the end of the face element; throws "truncated"
/// when the file is shorter than the header promises. Returns the offset of
/// the first byte after the faces.
inline std::size_t check_binary_size(const std::string& path, const PlyHeader& h, const PlyLayout& l,
                                     const std::string& bytes) {
  const bool be = h.format == PlyFormat::BinaryBE;
  const std::size_t nv = h.elements[l.vertex_element].count, nf = h.elements[l.face_element].count;
  // Lower bound from fixed sizes (a face list may be empty: such faces are
  // dropped, not an error).
  std::size_t minimum = h.body_offset;
  for (std::size_t e = 0; e <= l.face_element; ++e) {
    std::size_t stride = 0;
    for (const PlyProperty& p : h.elements[e].properties)
      stride += p.is_list ? type_size(p.count_type) : type_size(p.type);
    minimum += h.elements[e].count * stride;
  }
  auto truncated = [&](const std::string& detail) {
    return InputError(path, "truncated file: " + std::to_string(bytes.size()) + " bytes, but the header's " +
                                std::to_string(nv) + " vertices and " + std::to_string(nf) + " faces need " + detail);
  };
  if (bytes.size() < minimum) throw truncated("at least " + std::to_string(minimum));
  std::size_t at = h.body_offset;
  for (std::size_t e = 0; e < l.face_element; ++e) {
    for (const PlyProperty& p : h.elements[e].properties) at += h.elements[e].count * type_size(p.type);
  }
  const auto& face = h.elements[l.face_element];
  for (std::size_t f = 0; f < face.count; ++f) {
    for (const PlyProperty& p : face.properties) {
      if (!p.is_list) {
        at += type_size(p.type);
        continue;
      }
      if (at + type_size(p.count_type) > bytes.size())
        throw truncated("more (file ends in face " + std::to_string(f) + ")");
      const long long n = read_count(bytes, at, p.count_type, be);
      if (n < 0) throw InputError(path, "face " + std::to_string(f) + " has a negative vertex count");
      at += type_size(p.count_type) + static_cast<std::size_t>(n) * type_size(p.type);
    }
    if (at > bytes.size()) throw truncated("more (file ends in face " + std::to_string(f) + ")");
  }
  return at;
}

/// The whitespace-separated tokens of `line` into `out` (cleared first; the
/// caller reuses it from line to line).
inline void split_tokens(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  for (std::size_t a = 0; a < line.size();) {
    const std::size_t b = line.find_first_of(" \t\r", a);
    const std::size_t end = b == std::string_view::npos ? line.size() : b;
    if (end > a) out.push_back(line.substr(a, end - a));
    a = end + 1;
  }
}

/// One ASCII token as a value of type `t`: InputError naming `where()` (only
/// called on failure) for a token that is not a number of that type, or not
/// finite, or out of range.
template <class Where>
double ascii_value(const std::string& path, std::string_view token, PlyType t, const Where& where) {
  auto fail = [&](const std::string& why) {
    return InputError(path, where() + ": '" + std::string(token.substr(0, 32)) + "' " + why);
  };
  if (is_float(t)) {
    double v = 0.0;
    const std::string_view body = !token.empty() && token[0] == '+' ? token.substr(1) : token;
    const auto r = std::from_chars(body.data(), body.data() + body.size(), v);
    if (r.ec == std::errc::result_out_of_range) throw fail("is out of range for " + std::string(type_name(t)));
    if (r.ec != std::errc() || r.ptr != body.data() + body.size()) throw fail("is not a number");
    if (!std::isfinite(v)) throw fail("is not a finite number");
    if (t == PlyType::Float32 && std::abs(v) > 3.4028234663852886e38) throw fail("is out of range for float");
    return v;
  }
  long long v = 0;
  const auto r = std::from_chars(token.data(), token.data() + token.size(), v);
  static const long long lo[] = {-128, 0, -32768, 0, -2147483648LL, 0};
  static const long long hi[] = {127, 255, 32767, 65535, 2147483647LL, 4294967295LL};
  const int k = static_cast<int>(t);
  if (r.ec != std::errc() || r.ptr != token.data() + token.size()) throw fail("is not an integer");
  if (v < lo[k] || v > hi[k]) throw fail("is out of range for " + std::string(type_name(t)));
  return static_cast<double>(v);
}

/// Checks an ASCII body up to the end of the face element, one element per
/// line, every token a value of its property's type: a short or long line, a
/// bad token, a non-finite value or a negative list count is an InputError
/// naming the line, so OpenMesh (which reads tokens with no notion of lines)
/// only ever sees a well-formed body and a line one value short cannot shift
/// the data. Returns the offset of the first byte after the faces.
inline std::size_t check_ascii_body(const std::string& path, const PlyHeader& h, const PlyLayout& l,
                                    const std::string& bytes) {
  std::size_t pos = h.body_offset;
  int line_no = 0;
  for (std::size_t e = 0; e <= l.face_element; ++e) {
    const PlyElement& el = h.elements[e];
    std::vector<std::string_view> tok;
    for (std::size_t i = 0; i < el.count; ++i) {
      // Messages are built only for a bad line (this loop runs once per element).
      auto where = [&] { return el.name + " " + std::to_string(i); };
      std::string_view line;
      bool at_end = false;  // the line runs to the end of the file (no newline): a cut file
      do {                  // the next non-blank line
        if (pos >= bytes.size()) {
          throw InputError(path, "truncated file: the body ends before " + where() + " (the header promises " +
                                     std::to_string(el.count) + " " + el.name + " lines)");
        }
        std::size_t eol = bytes.find('\n', pos);
        at_end = eol == std::string::npos;
        if (at_end) eol = bytes.size();
        line = std::string_view(bytes).substr(pos, eol - pos);
        pos = eol + 1;
        ++line_no;
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t'))
          line.remove_suffix(1);
        while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
      } while (line.empty());
      split_tokens(line, tok);
      auto at = [&] { return "body line " + std::to_string(line_no) + " (" + where() + ")"; };
      auto short_line = [&](const std::string& what) {
        if (at_end) return InputError(path, "truncated file: the body ends inside " + where());
        return InputError(path, at() + ": " + what);
      };
      std::size_t k = 0;
      for (const PlyProperty& p : el.properties) {
        if (k >= tok.size()) throw short_line("too few values on the line");
        if (!p.is_list) {
          ascii_value(path, tok[k++], p.type, at);
          continue;
        }
        const auto n = static_cast<std::size_t>(ascii_value(path, tok[k++], p.count_type, at));
        if (n > tok.size() - k) throw short_line("the list promises " + std::to_string(n) + " values");
        for (std::size_t j = 0; j < n; ++j) ascii_value(path, tok[k++], p.type, at);
      }
      if (k != tok.size()) {
        throw InputError(
            path, at() + ": " + std::to_string(tok.size()) + " values on the line, expected " + std::to_string(k));
      }
    }
  }
  return std::min(pos, bytes.size());
}

/// The velocity triples tried, in order, for `attr` (see ReadOptions).
inline std::vector<std::array<std::string, 3>> velocity_candidates(const std::string& path, const std::string& attr) {
  if (attr.empty()) return {{"vx", "vy", "vz"}, {"velocity_x", "velocity_y", "velocity_z"}, {"v_x", "v_y", "v_z"}};
  if (attr.find(',') == std::string::npos)
    return {{attr + "_x", attr + "_y", attr + "_z"}, {attr + "x", attr + "y", attr + "z"}};
  std::array<std::string, 3> names;
  std::istringstream in(attr);
  std::string part;
  int n = 0;
  while (std::getline(in, part, ',')) {
    const auto b = part.find_first_not_of(" \t"), e = part.find_last_not_of(" \t");
    if (n == 3 || b == std::string::npos)
      throw InputError(path, "--velocity-attr '" + attr + "' must be three comma-separated names or one prefix");
    names[n++] = part.substr(b, e - b + 1);
  }
  if (n != 3)
    throw InputError(path, "--velocity-attr '" + attr + "' must be three comma-separated names or one prefix");
  return {names};
}

/// The index of the vertex property `name`; InputError unless it is float or
/// double (`what` it holds names it).
inline int float_property(const std::string& path, const PlyElement& vertex, const std::string& name,
                          const char* what) {
  const int i = vertex.find(name);
  if (!is_float(vertex.properties[i].type))
    throw InputError(path, std::string("wrong property type for ") + what + " '" + name +
                               "': " + type_name(vertex.properties[i].type) + " (expected float or double)");
  return i;
}

/// Sets the velocity properties of `l` from the first candidate names
/// (velocity_candidates) the vertex has; InputError naming those tried when
/// none.
inline void find_velocity_properties(const std::string& path, const PlyElement& vertex,
                                     const std::string& velocity_attr, PlyLayout& l) {
  std::string tried;
  for (const auto& c : velocity_candidates(path, velocity_attr)) {
    tried += (tried.empty() ? "" : ", ") + c[0] + "/" + c[1] + "/" + c[2];
    if (vertex.find(c[0]) < 0 || vertex.find(c[1]) < 0 || vertex.find(c[2]) < 0) continue;
    for (int a = 0; a < 3; ++a) {
      l.velocity_prop[a] = float_property(path, vertex, c[a], "velocity");
      l.velocity_type[a] = vertex.properties[l.velocity_prop[a]].type;
    }
    l.has_velocity = true;
    return;
  }
  throw InputError(path, "no velocity properties (tried " + tried +
                             "); name them with --velocity-attr or use --velocity-from-positions");
}

/// InputError unless the face element's first property is its integer
/// vertex_indices (or vertex_index) list.
inline void check_face_indices(const std::string& path, const PlyElement& face) {
  const bool first_is_indices =
      !face.properties.empty() && face.properties[0].is_list &&
      (face.properties[0].name == "vertex_indices" || face.properties[0].name == "vertex_index");
  if (!first_is_indices) {
    const bool later = face.find("vertex_indices") >= 0 || face.find("vertex_index") >= 0;
    throw InputError(path, later ? "unsupported PLY layout: vertex_indices must be the first face property"
                                 : "faces have no vertex_indices list");
  }
  if (is_float(face.properties[0].type))
    throw InputError(path, std::string("wrong property type for face indices: ") + type_name(face.properties[0].type) +
                               " (expected an integer type)");
}

/// Validates the header against what fluidtex needs and returns the layout.
inline PlyLayout plan_ply_read(const std::string& path, const PlyHeader& h, const std::string& bytes,
                               const std::string& velocity_attr, bool require_velocities) {
  PlyLayout l;
  int vi = -1, fi = -1;
  for (std::size_t e = 0; e < h.elements.size(); ++e) {
    if (h.elements[e].name == "vertex" && vi < 0) vi = static_cast<int>(e);
    if (h.elements[e].name == "face" && fi < 0) fi = static_cast<int>(e);
  }
  // A header without a vertex or a face element is not a mesh; one whose
  // elements are empty is a frame without liquid (a solver writes those
  // before an inflow has filled anything).
  if (vi < 0) throw InputError(path, "empty mesh (no vertex element)");
  if (fi < 0) throw InputError(path, "empty mesh (no face element: a point cloud?)");
  if (h.elements[vi].count == 0) throw InputError(path, std::string("empty mesh (no vertices") + kNoLiquidHint + ")");
  if (h.elements[fi].count == 0) throw InputError(path, std::string("empty mesh (no faces") + kNoLiquidHint + ")");
  if (fi < vi) throw InputError(path, "unsupported PLY layout: the face element precedes the vertex element");
  l.vertex_element = vi;
  l.face_element = fi;
  for (int e = 0; e < fi; ++e) {
    for (const PlyProperty& p : h.elements[e].properties)
      if (p.is_list)
        throw InputError(path, "unsupported PLY layout: list property '" + p.name + "' on element '" +
                                   h.elements[e].name + "' before the faces");
  }
  const PlyElement& vertex = h.elements[vi];
  const char* axes[] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    if (vertex.find(axes[a]) < 0) throw InputError(path, "no vertex positions (property x, y or z missing)");
    l.position_prop[a] = float_property(path, vertex, axes[a], "position");
    l.position_type[a] = vertex.properties[l.position_prop[a]].type;
  }
  if (require_velocities) find_velocity_properties(path, vertex, velocity_attr, l);
  check_face_indices(path, h.elements[fi]);
  l.body_end =
      h.format == PlyFormat::Ascii ? check_ascii_body(path, h, l, bytes) : check_binary_size(path, h, l, bytes);
  return l;
}

/// The header OpenMesh reads: positions and velocities renamed to custom
/// properties (read at their declared precision instead of through Vec3f),
/// other properties renamed so that none triggers OpenMesh's special
/// handling, list counts mapped to the same-size type OpenMesh accepts, and a
/// trailing empty "vertex" element with x/y/z, which is never read but
/// satisfies read_ascii's "vertex dimension 3" check.
inline std::string canonical_ply_header(const PlyHeader& h, const PlyLayout& l) {
  static const char* formats[] = {"ascii", "binary_little_endian", "binary_big_endian"};
  static const char* counts[] = {"uchar", "uchar", "uint16", "uint16", "int", "int"};
  std::string s = std::string("ply\nformat ") + formats[static_cast<int>(h.format)] + " 1.0\n";
  for (std::size_t e = 0; e <= l.face_element; ++e) {  // elements after the faces are not read
    const PlyElement& el = h.elements[e];
    s += "element " + el.name + " " + std::to_string(el.count) + "\n";
    for (std::size_t i = 0; i < el.properties.size(); ++i) {
      const PlyProperty& p = el.properties[i];
      std::string name = "fluidtex_e" + std::to_string(e) + "_" + std::to_string(i);
      for (int a = 0; a < 3 && e == l.vertex_element; ++a) {
        if (static_cast<int>(i) == l.position_prop[a]) name = canonical_position_name(a);
        if (l.has_velocity && static_cast<int>(i) == l.velocity_prop[a]) name = canonical_velocity_name(a);
      }
      if (e == l.face_element && i == 0) name = "vertex_indices";
      s += p.is_list ? std::string("property list ") + counts[static_cast<int>(p.count_type)] + " " +
                           type_name(p.type) + " " + name + "\n"
                     : std::string("property ") + type_name(p.type) + " " + name + "\n";
    }
  }
  return s + "element vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
}

}  // namespace fluidtex::plyio
