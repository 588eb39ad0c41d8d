/// @file options.h
/// @brief Options defined once. Every options struct lists its user-facing
/// fields in one static `for_each_option(self, f)`, calling
/// `f(OptionInfo, field)` per field: the option's name, help, accepted values
/// and the field it sets. Validation (`check_options`), the command line,
/// `--help`, `--print-config`, `--config` and `OUT/job.toml` are all generated
/// from those lists (job/job_options.h assembles the job's table), and the
/// state file's settings block is written in the same order.
///
/// Field types: double, int, std::uint64_t, bool (a flag), std::string,
/// std::vector<std::string> (a comma list), an enum with an EnumName table
/// (util/enum_names.h), and std::optional<double> for a length fluidtex
/// derives when it is not given (spelled "auto").
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "fluidtex/util/enum_names.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/strings.h"

namespace fluidtex {

/// The interval a numeric option accepts (always finite).
struct Bounds {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false, max_open = false;

  bool contains(double v) const;
  /// "must be > 0", "must be >= 1", "must be in [-1, 1)", "must be finite".
  std::string describe() const;
};
constexpr Bounds at_least(double v) { return {v, std::numeric_limits<double>::infinity(), false, false}; }
constexpr Bounds above(double v) { return {v, std::numeric_limits<double>::infinity(), true, false}; }
/// [lo, hi] with either end open on request.
constexpr Bounds between(double lo, double hi, bool lo_open = false, bool hi_open = false) {
  return {lo, hi, lo_open, hi_open};
}

/// What an option is to a job's record (job/job_record.h): whether
/// `run --resume` must give the job's value, whether it goes into the
/// settings hash stamped in the atlases, and whether job.toml holds it as an
/// absolute path. Declared with the option, so that a new option cannot
/// change resume behaviour by being left off a list elsewhere.
enum class OptionRole : std::uint8_t {
  Method,      ///< changes what the job writes: compared at --resume and hashed (the default)
  Mode,        ///< how this run makes the files (--track-only): compared at --resume, not hashed
  OutputPath,  ///< where the job writes: absolute in job.toml, compared at --resume as a path, not hashed
  InputPath,   ///< what the job reads, checked by content (mesh fingerprints, SHA-1): absolute in job.toml only
  Free,        ///< changes nothing the job writes (threads, resume, frames by their own rule): neither
};

struct OptionInfo {
  const char* name;                      ///< long flag without "--", and the config key
  const char* help;                      ///< one line for --help and the config comment
  Bounds bounds = {};                    ///< numeric options
  const char* alias = "";                ///< short flag, e.g. "-i"
  const char* choices = "";              ///< comma list of the names a list or text option accepts
  const char* group = "";                ///< --help section; empty: the section of the caller
  OptionRole role = OptionRole::Method;  ///< what the option is to a job's record
  bool positional = false;               ///< a command's argument, given without a flag (NAME in --help)
  bool required = false;                 ///< the command refuses to run without it
};

/// InputError "--NAME ..." unless `field` satisfies `info`.
void check_option(const OptionInfo& info, double field);
void check_option(const OptionInfo& info, int field);
void check_option(const OptionInfo& info, const std::optional<double>& field);
void check_option(const OptionInfo& info, const std::vector<std::string>& field);
void check_option(const OptionInfo& info, const std::string& field);  // one of info.choices, when it has some
template <class T>
void check_option(const OptionInfo&, const T&) {}  // flags, seeds, enums: every value is valid

/// Checks every option `S::for_each_option` lists.
template <class S>
void check_options(const S& s) {
  S::for_each_option(s, [](const OptionInfo& info, const auto& field) { check_option(info, field); });
}

/// One option bound to its field, with the type erased: what the command
/// line and the config files need.
struct OptionRef {
  enum class Kind {
    Flag,   ///< bool: given without a value on the command line
    Value,  ///< one value
    List,   ///< a comma list
  };
  OptionInfo info;
  Kind kind = Kind::Value;
  std::vector<std::string> choices;  ///< enum names, or the names a list accepts
  /// The value as text: numbers and flags as written, strings unquoted, a
  /// list comma-separated, an unset automatic length "auto".
  std::function<std::string()> text;
  /// Parses and stores `values` (one element unless a list); InputError
  /// "--NAME: ..." for text that is not a value of the option's type.
  std::function<void(const std::vector<std::string>&)> set;
  /// InputError "--NAME ..." unless the value is in the accepted range.
  std::function<void()> check;
  /// The value as a config file writes it (strings quoted).
  std::function<std::string()> toml;
  /// The value's kind as --help shows it: FLOAT, INT, TEXT, ...
  const char* type = "TEXT";
  /// The option may be left to fluidtex ("auto": a std::optional field).
  bool automatic = false;
};

namespace option_detail {
double parse_number(const std::string& name, const std::string& text);
long long parse_integer(const std::string& name, const std::string& text, long long min, long long max);
unsigned long long parse_unsigned(const std::string& name, const std::string& text, unsigned long long max);
bool parse_flag(const std::string& name, const std::string& text);
std::vector<std::string> split_choices(const char* list);
const std::string& single(const std::string& name, const std::vector<std::string>& values);
/// A TOML basic string, or a literal one when `text` holds a '"' (the
/// config reader does not unescape).
std::string toml_string(const std::string& name, const std::string& text);

/// bind_option for a number or "auto" (FLOAT|auto), a list (its choices from
/// ref.info), and an integer of type T (INT, bounded by T's range).
void bind_automatic(OptionRef& ref, std::optional<double>& field);
void bind_list(OptionRef& ref, std::vector<std::string>& field);
template <class T>
void bind_integer(OptionRef& ref, T& field) {
  ref.type = "INT";
  ref.text = [&field] { return std::to_string(field); };
  ref.set = [&field, name = std::string(ref.info.name)](const std::vector<std::string>& v) {
    const std::string& s = single(name, v);
    if constexpr (std::is_unsigned_v<T>)
      field = static_cast<T>(parse_unsigned(name, s, std::numeric_limits<T>::max()));
    else
      field = static_cast<T>(parse_integer(name, s, std::numeric_limits<T>::min(), std::numeric_limits<T>::max()));
  };
}
}  // namespace option_detail

/// `field` behind an OptionRef (see the field types in the file comment).
template <class T>
OptionRef bind_option(const OptionInfo& info, T& field) {
  namespace d = option_detail;
  OptionRef ref;
  ref.info = info;
  const std::string name = info.name;
  if constexpr (std::is_same_v<T, bool>) {
    ref.kind = OptionRef::Kind::Flag;
    ref.text = [&field] { return std::string(field ? "true" : "false"); };
    ref.set = [&field, name](const std::vector<std::string>& v) { field = d::parse_flag(name, d::single(name, v)); };
  } else if constexpr (std::is_same_v<T, double>) {
    ref.type = "FLOAT";
    ref.text = [&field] { return format_number(field); };
    ref.set = [&field, name](const std::vector<std::string>& v) { field = d::parse_number(name, d::single(name, v)); };
  } else if constexpr (std::is_same_v<T, std::optional<double>>) {
    d::bind_automatic(ref, field);
  } else if constexpr (std::is_integral_v<T>) {
    d::bind_integer(ref, field);
  } else if constexpr (std::is_same_v<T, std::string>) {
    ref.choices = d::split_choices(info.choices);
    ref.text = [&field] { return field; };
    ref.set = [&field, name](const std::vector<std::string>& v) { field = d::single(name, v); };
  } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
    d::bind_list(ref, field);
  } else {
    static_assert(std::is_enum_v<T>, "unsupported option type");
    ref.choices = enum_choices<T>();
    ref.text = [&field] { return std::string(enum_name(field)); };
    ref.set = [&field, name](const std::vector<std::string>& v) { field = parse_enum<T>(d::single(name, v), name); };
  }
  ref.check = [&field, info] { check_option(info, field); };
  if (!ref.toml) {
    const bool quoted =
        std::is_same_v<T, std::string> || std::is_same_v<T, std::vector<std::string>> || std::is_enum_v<T>;
    ref.toml = [text = ref.text, quoted, name] { return quoted ? d::toml_string(name, text()) : text(); };
  }
  return ref;
}

/// The options as a TOML document (what --print-config prints and
/// OUT/job.toml holds): a comment per --help section and per option, then
/// `name=value`.
std::string format_toml(const std::vector<OptionRef>& options);

/// One `key=value` of a config file: the value's elements (one unless an
/// array), quotes removed.
struct ConfigEntry {
  std::string name;
  std::vector<std::string> values;
};
/// The entries of a TOML config file in `table` (for "run": the top level
/// and `[run]`; other tables are skipped), in file order. InputError naming
/// the file when it cannot be read or is not TOML.
std::vector<ConfigEntry> read_config_file(const std::string& path, const std::string& table = "run");

/// Applies `entries` to the options of `table` for which `skip(name)` is
/// false (the command line's own values win). InputError naming `path` for a
/// key no option has or a value it rejects.
void apply_config(const std::vector<ConfigEntry>& entries, const std::vector<OptionRef>& table, const std::string& path,
                  const std::function<bool(const std::string&)>& skip);

}  // namespace fluidtex
