/// @file json.h
/// @brief JSON text as fluidtex writes it (stats.jsonl, eval's metrics and
/// summaries, `info --json`, `--log-format json`): numbers locale-independent
/// and the shortest that round-trips (std::to_chars), non-finite numbers as
/// null, strings escaped (UTF-8 passes through). The same values always give
/// the same bytes.
#pragma once

#include <charconv>
#include <string>
#include <utility>
#include <vector>

namespace fluidtex {

/// `v` as a JSON number (shortest round trip; null when not finite).
std::string json_number(double v);

/// `text` as a JSON string: quoted, escaped (UTF-8 passes through).
std::string json_string(const std::string& text);

/// A flat JSON object of numbers, keys in the given order.
std::string to_json_object(const std::vector<std::pair<std::string, double>>& values);

/// Appending forms, for objects written field by field.
void append_json_string(std::string& out, const std::string& text);
void append_json_number(std::string& out, double v);
/// `"key":`, preceded by a comma unless it is the object's first.
void append_json_key(std::string& out, const std::string& key, bool first = false);
template <typename Int>
void append_json_integer(std::string& out, Int v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

}  // namespace fluidtex
