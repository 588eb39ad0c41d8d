// stats.jsonl writer (see frame_stats.h).
#include "fluidtex/job/frame_stats.h"

#include <charconv>
#include <filesystem>
#include <fstream>

#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/json.h"

namespace fluidtex {

namespace {

/// The frame number of a line written by to_json_line, if it has one.
bool frame_of_line(const std::string& line, int* frame) {
  static const std::string prefix = "{\"frame\":";
  if (line.compare(0, prefix.size(), prefix) != 0) return false;
  const char* begin = line.data() + prefix.size();
  const auto r = std::from_chars(begin, line.data() + line.size(), *frame);
  return r.ec == std::errc() && r.ptr != begin;
}

}  // namespace

std::string to_json_line(const FrameStats& stats) {
  std::string out = "{";
  append_json_key(out, "frame", true);
  append_json_integer(out, stats.frame);
  if (!stats.method.empty()) {
    append_json_key(out, "method");
    append_json_string(out, stats.method);
  }
  append_json_key(out, "vertices");
  append_json_integer(out, stats.vertices);
  append_json_key(out, "faces");
  append_json_integer(out, stats.faces);

  append_json_key(out, "patches");
  out += '{';
  append_json_key(out, "fading_in", true);
  append_json_integer(out, stats.patches.fading_in);
  append_json_key(out, "active");
  append_json_integer(out, stats.patches.active);
  append_json_key(out, "fading_out_distorted");
  append_json_integer(out, stats.patches.fading_out_distorted);
  append_json_key(out, "fading_out_close");
  append_json_integer(out, stats.patches.fading_out_close);
  out += '}';

  append_json_key(out, "seconds");
  out += '{';
  bool first = true;
  for (const auto& [name, value] : stats.seconds) {
    append_json_key(out, name, first);
    append_json_number(out, value);
    first = false;
  }
  out += '}';

  append_json_key(out, "uncovered_fraction");
  append_json_number(out, stats.uncovered_fraction);
  for (const auto& [name, value] : stats.extra) {
    append_json_key(out, name);
    append_json_number(out, value);
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
