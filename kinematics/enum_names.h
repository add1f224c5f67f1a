// An enum's values and their names in one table, which both directions read: the name of a value
// (for files, flags and messages) and the value of a name. A ToString switch beside a Parse chain
// writes every name twice, and a new value can be added to one and missed in the other.
#pragma once

#include <cstddef>
#include <string>

namespace tavis::kinematics {

template <typename Enum>
struct EnumName {
  Enum value;
  const char* name;
};

// The name of `value` in `names`; `unknown` for a value the table lacks (a bug: every value has one).
template <typename Enum, std::size_t N>
const char* NameOf(const EnumName<Enum> (&names)[N], Enum value, const char* unknown) {
  for (const EnumName<Enum>& entry : names) {
    if (entry.value == value) return entry.name;
  }
  return unknown;
}

// The entry named `text`, or null.
template <typename Enum, std::size_t N>
const EnumName<Enum>* FindNamed(const EnumName<Enum> (&names)[N], const std::string& text) {
  for (const EnumName<Enum>& entry : names) {
    if (text == entry.name) return &entry;
  }
  return nullptr;
}

// Every name in table order, for messages and help: "serial, per-env, batched".
template <typename Enum, std::size_t N>
std::string NameList(const EnumName<Enum> (&names)[N]) {
  std::string list;
  for (const EnumName<Enum>& entry : names) list += (list.empty() ? "" : ", ") + std::string(entry.name);
  return list;
}

}  // namespace tavis::kinematics
