#include "fluidtex/util/options.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include <CLI/CLI.hpp>

#include "fluidtex/util/atomic_file.h"

namespace fluidtex {

namespace option_detail {

namespace {

template <class T>
bool parse_whole(const std::string& text, T& out) {
  const char* end = text.data() + text.size();
  const auto r = std::from_chars(text.data(), end, out);
  return r.ec == std::errc() && r.ptr == end;
}

}  // namespace

double parse_number(const std::string& name, const std::string& text) {
  double v = 0.0;
  // from_chars does not take a leading '+', which people write.
  const std::string body = !text.empty() && text[0] == '+' ? text.substr(1) : text;
  if (!parse_whole(body, v)) throw InputError("", "--" + name + ": expected a number, got '" + text + "'");
  return v;
}

long long parse_integer(const std::string& name, const std::string& text, long long min, long long max) {
  long long v = 0;
  const std::string body = !text.empty() && text[0] == '+' ? text.substr(1) : text;
  if (!parse_whole(body, v) || v < min || v > max) {
    throw InputError("", "--" + name + ": expected an integer in [" + std::to_string(min) + ", " + std::to_string(max) +
                             "], got '" + text + "'");
  }
  return v;
}

unsigned long long parse_unsigned(const std::string& name, const std::string& text, unsigned long long max) {
  unsigned long long v = 0;
  if (!parse_whole(text, v) || v > max) {
    throw InputError("", "--" + name + ": expected an integer in [0, " + std::to_string(max) + "], got '" + text + "'");
  }
  return v;
}

bool parse_flag(const std::string& name, const std::string& text) {
  if (text == "true" || text == "1") return true;
  if (text == "false" || text == "0") return false;
  throw InputError("", "--" + name + ": expected true or false, got '" + text + "'");
}

void bind_automatic(OptionRef& ref, std::optional<double>& field) {
  ref.type = "FLOAT|auto";
  ref.automatic = true;
  ref.text = [&field] { return field ? format_number(*field) : std::string("auto"); };
  ref.toml = [&field] { return field ? format_number(*field) : std::string("\"auto\""); };
  ref.set = [&field, name = std::string(ref.info.name)](const std::vector<std::string>& v) {
    const std::string& s = single(name, v);
    if (s == "auto")
      field.reset();
    else
      field = parse_number(name, s);
  };
}

void bind_list(OptionRef& ref, std::vector<std::string>& field) {
  ref.kind = OptionRef::Kind::List;
  ref.choices = split_choices(ref.info.choices);
  ref.text = [&field] {
    std::string s;
    for (const std::string& e : field) s += (s.empty() ? "" : ",") + e;
    return s;
  };
  ref.set = [&field](const std::vector<std::string>& v) {
    field.clear();
    for (const std::string& e : v) {
      for (const std::string& item : split_choices(e.c_str())) field.push_back(item);
    }
  };
}

std::vector<std::string> split_choices(const char* list) {
  std::vector<std::string> out;
  std::string item;
  for (const char* c = list; *c != '\0'; ++c) {
    if (*c == ',') {
      if (!item.empty()) out.push_back(item);
      item.clear();
    } else if (*c != ' ') {
      item += *c;
    }
  }
  if (!item.empty()) out.push_back(item);
  return out;
}

const std::string& single(const std::string& name, const std::vector<std::string>& values) {
  if (values.size() != 1) throw InputError("", "--" + name + ": expected one value");
  return values[0];
}

std::string toml_string(const std::string& name, const std::string& text) {
  if (text.find('"') == std::string::npos) return '"' + text + '"';
  if (text.find('\'') == std::string::npos) return '\'' + text + '\'';
  throw InputError("", "--" + name + ": a value with both ' and \" cannot be written to a config file");
}

}  // namespace option_detail

bool Bounds::contains(double v) const {
  if (!std::isfinite(v)) return false;
  const bool lo = min_open ? v > min : v >= min;
  const bool hi = max_open ? v < max : v <= max;
  return lo && hi;
}

std::string Bounds::describe() const {
  const bool has_min = std::isfinite(min), has_max = std::isfinite(max);
  if (has_min && has_max) {
    return "must be in " + std::string(min_open ? "(" : "[") + format_number(min) + ", " + format_number(max) +
           (max_open ? ")" : "]");
  }
  if (has_min) return std::string("must be ") + (min_open ? "> " : ">= ") + format_number(min);
  if (has_max) return std::string("must be ") + (max_open ? "< " : "<= ") + format_number(max);
  return "must be finite";
}

namespace {

template <class T>
void check_number(const OptionInfo& info, T v) {
  if (!info.bounds.contains(static_cast<double>(v))) {
    std::string text = format_number(static_cast<double>(v));
    throw InputError("", "--" + std::string(info.name) + " " + info.bounds.describe() + " (got " + text + ")");
  }
}

}  // namespace

void check_option(const OptionInfo& info, double field) { check_number(info, field); }
void check_option(const OptionInfo& info, int field) { check_number(info, field); }
void check_option(const OptionInfo& info, const std::optional<double>& field) {
  if (field && !info.bounds.contains(*field)) {
    throw InputError("", "--" + std::string(info.name) + " " + info.bounds.describe() + " or auto (got " +
                             format_number(*field) + ")");
  }
}
void check_option(const OptionInfo& info, const std::vector<std::string>& field) {
  const std::vector<std::string> choices = option_detail::split_choices(info.choices);
  if (choices.empty()) return;
  for (const std::string& value : field) {
    if (std::find(choices.begin(), choices.end(), value) != choices.end()) continue;
    throw InputError("", "--" + std::string(info.name) + ": unknown value '" + value + "' (use " + info.choices + ")");
  }
}

void check_option(const OptionInfo& info, const std::string& field) {
  const std::vector<std::string> choices = option_detail::split_choices(info.choices);
  if (choices.empty() || std::find(choices.begin(), choices.end(), field) != choices.end()) return;
  throw InputError("", "--" + std::string(info.name) + ": unknown value '" + field + "' (use " + info.choices + ")");
}

std::string format_toml(const std::vector<OptionRef>& options) {
  std::ostringstream out;
  std::string group;
  for (const OptionRef& o : options) {
    if (o.info.group != group) {
      group = o.info.group;
      out << "\n# " << group << "\n";
    }
    out << "\n# " << o.info.help << "\n" << o.info.name << '=' << o.toml() << '\n';
  }
  return out.str();
}

std::vector<ConfigEntry> read_config_file(const std::string& path, const std::string& table) {
  require_regular_file(path, "config file");  // a folder or a device would read as an empty file
  {
    // Binary data is refused before anything of it could reach a message.
    std::ifstream probe(path, std::ios::binary);
    char buf[4096];
    probe.read(buf, sizeof buf);
    for (std::streamsize i = 0; i < probe.gcount(); ++i) {
      const auto c = static_cast<unsigned char>(buf[i]);
      if (c == 0 || (c < 0x20 && c != '\t' && c != '\n' && c != '\r') || c == 0x7f)
        throw InputError(path, "not a TOML text file (binary data)");
    }
  }
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot read config file");
  // CLI11 2.1 cuts a value at the first '#' even inside quotes
  // (input="mesh.####.ply" would read back as "mesh."), so comments are
  // stripped here, outside quotes only, and CLI11 is told nothing else starts one.
  std::stringstream clean;
  for (std::string line; std::getline(in, line);) {
    char quote = 0;
    for (std::size_t k = 0; k < line.size(); ++k) {
      const char c = line[k];
      if (quote == '"' && c == '\\') {
        ++k;  // an escaped character inside a basic string
      } else if (quote != 0) {
        if (c == quote) quote = 0;
      } else if (c == '"' || c == '\'') {
        quote = c;
      } else if (c == '#') {
        line.erase(k);
        break;
      }
    }
    clean << line << '\n';
  }
  CLI::ConfigTOML toml;
  toml.comment('\0');
  std::vector<CLI::ConfigItem> items;
  try {
    items = toml.from_config(clean);
  } catch (const CLI::ParseError& e) {
    throw InputError(path, std::string("malformed config file: ") + e.what());
  }
  std::vector<ConfigEntry> entries;
  for (const CLI::ConfigItem& item : items) {
    if (item.name == "++" || item.name == "--") continue;  // section markers
    const bool top = item.parents.empty() && table == "run";
    if (!top && !(item.parents.size() == 1 && item.parents[0] == table)) continue;
    entries.push_back({item.name, item.inputs});
  }
  return entries;
}

void apply_config(const std::vector<ConfigEntry>& entries, const std::vector<OptionRef>& table, const std::string& path,
                  const std::function<bool(const std::string&)>& skip) {
  for (const ConfigEntry& entry : entries) {
    const auto it =
        std::find_if(table.begin(), table.end(), [&](const OptionRef& o) { return entry.name == o.info.name; });
    if (it == table.end()) {
      const std::string shown = entry.name.size() > 60 ? entry.name.substr(0, 60) + "…" : entry.name;
      throw InputError(path, "unknown option '" + shown + "'");
    }
    if (skip(entry.name)) continue;
    try {
      it->set(entry.values);
      it->check();
    } catch (const InputError& e) {
      throw InputError(path, e.what());
    }
  }
}

}  // namespace fluidtex
