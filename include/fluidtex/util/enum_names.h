/// @file enum_names.h
/// @brief Enum options defined once: each enum declares, next to itself, the
/// names its values are spelled with (options, config files, state files,
/// reports), in the order `--help` and error messages list them:
///
///   inline constexpr EnumName<Blend> kBlendNames[] = {{Blend::ContrastPreserving, "contrast"}, ...};
///   constexpr const auto& enum_names(Blend) { return kBlendNames; }
///
/// and these templates give the name of a value, the value of a name and the
/// list of choices from that one table.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fluidtex/util/error.h"

namespace fluidtex {

template <class E>
struct EnumName {
  E value;
  const char* name;
};

/// The name of `value` ("?" for a value the table lacks).
template <class E>
const char* enum_name(E value) {
  for (const auto& [v, name] : enum_names(E{})) {
    if (v == value) return name;
  }
  return "?";
}

/// Every name, in table order.
template <class E>
std::vector<std::string> enum_choices() {
  std::vector<std::string> out;
  for (const auto& entry : enum_names(E{})) out.emplace_back(entry.name);
  return out;
}

/// The value whose underlying integer is `raw` (as a binary file stores it),
/// when E's table has one.
template <class E>
bool enum_from_raw(std::uint64_t raw, E& out) {
  for (const auto& [v, name] : enum_names(E{})) {
    if (static_cast<std::uint64_t>(v) == raw) {
      out = v;
      return true;
    }
  }
  return false;
}

/// The value named `s`; otherwise InputError "--OPTION must be a, b or c
/// (got 's')".
template <class E>
E parse_enum(const std::string& s, const std::string& option) {
  for (const auto& [v, name] : enum_names(E{})) {
    if (s == name) return v;
  }
  const std::vector<std::string> choices = enum_choices<E>();
  std::string list;
  for (std::size_t k = 0; k < choices.size(); ++k) {
    list += (k == 0 ? "" : k + 1 == choices.size() ? " or " : ", ") + choices[k];
  }
  throw InputError("", "--" + option + " must be " + list + " (got '" + s + "')");
}

}  // namespace fluidtex
