// stats.jsonl writer (see stats.h).
//
// Numbers are formatted with std::to_chars (locale-independent, shortest
// representation that round-trips), so the same stats always give the same
// bytes; non-finite numbers become JSON null.
#include "fluidtex/io/stats.h"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/error.h"

namespace fluidtex {

namespace {

void append_escaped(std::string& out, const std::string& s) {
  static const char* hex = "0123456789abcdef";
  out += '"';
  for (const char ch : s) {
    const auto u = static_cast<unsigned char>(ch);
    switch (ch) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\b': out += "\\b"; break;
      case '\f': out += "\\f"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (u < 0x20 || u == 0x7f) {
          out += "\\u00";
          out += hex[u >> 4];
          out += hex[u & 0xf];
        } else {
          out += ch;  // UTF-8 bytes pass through
        }
    }
  }
  out += '"';
}

void append_number(std::string& out, double v) {
  if (!std::isfinite(v)) {
    out += "null";
    return;
  }
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

template <typename Int>
void append_integer(std::string& out, Int v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

void append_key(std::string& out, const std::string& key, bool first = false) {
  if (!first) out += ',';
  append_escaped(out, key);
  out += ':';
}

/// The frame number of a line written by to_json_line, if it has one.
bool frame_of_line(const std::string& line, int* frame) {
  static const std::string prefix = "{\"frame\":";
  if (line.compare(0, prefix.size(), prefix) != 0) return false;
  const char* begin = line.data() + prefix.size();
  const auto r = std::from_chars(begin, line.data() + line.size(), *frame);
  return r.ec == std::errc() && r.ptr != begin;
}

}  // namespace

std::string json_number(double v) {
  std::string out;
  append_number(out, v);
  return out;
}

std::string json_string(const std::string& text) {
  std::string out;
  append_escaped(out, text);
  return out;
}

std::string to_json_object(const std::vector<std::pair<std::string, double>>& values) {
  std::string out = "{";
  for (std::size_t k = 0; k < values.size(); ++k) {
    append_key(out, values[k].first, k == 0);
    append_number(out, values[k].second);
  }
  return out + "}";
}

std::string to_json_line(const FrameStats& stats) {
  std::string out = "{";
  append_key(out, "frame", true);
  append_integer(out, stats.frame);
  if (!stats.method.empty()) {
    append_key(out, "method");
    append_escaped(out, stats.method);
  }
  append_key(out, "vertices");
  append_integer(out, stats.vertices);
  append_key(out, "faces");
  append_integer(out, stats.faces);

  append_key(out, "patches");
  out += '{';
  append_key(out, "fading_in", true);
  append_integer(out, stats.patches.fading_in);
  append_key(out, "active");
  append_integer(out, stats.patches.active);
  append_key(out, "fading_out_distorted");
  append_integer(out, stats.patches.fading_out_distorted);
  append_key(out, "fading_out_close");
  append_integer(out, stats.patches.fading_out_close);
  out += '}';

  append_key(out, "seconds");
  out += '{';
  bool first = true;
  for (const auto& [name, value] : stats.seconds) {
    append_key(out, name, first);
    append_number(out, value);
    first = false;
  }
  out += '}';

  append_key(out, "uncovered_fraction");
  append_number(out, stats.uncovered_fraction);
  for (const auto& [name, value] : stats.extra) {
    append_key(out, name);
    append_number(out, value);
  }
  out += '}';
  return out;
}

StatsWriter::StatsWriter(std::string path, bool append_existing) : path_(std::move(path)) {
  if (!append_existing) {
    // Start from an empty file so stale lines of an earlier run never sit
    // next to this run's outputs.
    write_text_atomically(path_, "");
    return;
  }
  std::error_code ec;
  if (!std::filesystem::exists(path_, ec)) return;
  std::ifstream in(path_, std::ios::binary);
  if (!in) throw InputError(path_, "cannot read existing stats file");
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty()) lines_.push_back(line);
  }
}

void StatsWriter::add(const FrameStats& stats) {
  std::string line = to_json_line(stats);
  // A resumed run may redo a frame whose line was already written: replace it
  // rather than listing the frame twice.
  bool replaced = false;
  for (std::string& existing : lines_) {
    int frame = 0;
    if (frame_of_line(existing, &frame) && frame == stats.frame) {
      existing = line;
      replaced = true;
      break;
    }
  }
  if (!replaced) lines_.push_back(std::move(line));

  std::string text;
  for (const std::string& l : lines_) {
    text += l;
    text += '\n';
  }
  write_text_atomically(path_, text);
}

}  // namespace fluidtex
