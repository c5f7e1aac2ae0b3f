#pragma once
// An enum's values and their names in one table, so that each enum's names are written once:
// the name of a value (logs, summaries, the command line's choices) and the value of a name.
#include <cstddef>
#include <string>
#include <string_view>

#include "varsfm/util/error.h"

namespace varsfm {

template <typename Enum>
struct EnumName {
  Enum value;
  std::string_view name;
};

// The name of `value` in `table`; "?" for a value the table lacks.
template <typename Enum, size_t N>
constexpr std::string_view NameOf(const EnumName<Enum> (&table)[N], Enum value) {
  for (const EnumName<Enum>& entry : table)
    if (entry.value == value) return entry.name;
  return "?";
}

// The value `table` names `name`; throws varsfm::Error "unknown WHAT 'NAME' (a | b | c)" for a
// name it lacks.
template <typename Enum, size_t N>
Enum ValueOf(const EnumName<Enum> (&table)[N], std::string_view name, std::string_view what) {
  std::string names;
  for (const EnumName<Enum>& entry : table) {
    if (entry.name == name) return entry.value;
    names += (names.empty() ? "" : " | ") + std::string(entry.name);
  }
  Fail("unknown {} '{}' ({})", what, name, names);
}

}  // namespace varsfm
