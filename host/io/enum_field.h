// enum_field.h — one table-driven check for a scene string that must be one of a few names.
//
// Each scene section lists its choices as a table of {name, value}; readEnum returns the
// value whose name the string is, or fails with one line listing the allowed names in the
// table's order. Two wordings exist in the scene format and both are kept as they were:
//   Expected: `key: is "x", expected "a", "b" or "c"`
//   MustBe:   `key: must be "a", "b" or "c", not "x"`
#pragma once

#include <cstddef>
#include <string>

#include "io/json_util.h"

namespace clhair {

template <class E>
struct EnumName {
  const char* name;
  E value;
};

enum class EnumWording { Expected, MustBe };

// The names joined for a message: `"a", "b" or "c"` (quoted) or `a, b or c`.
std::string enumNameList(const char* const* names, std::size_t count, bool quoted);

// Fails at `key` of `o`: `value` is none of `names`, worded as `wording` says.
[[noreturn]] void failEnum(const JsonReader& o, const std::string& key, const std::string& value,
                           const char* const* names, std::size_t count, EnumWording wording);

// Finds `value` among the table's names; false when it is none of them.
template <class E, std::size_t N>
bool findEnum(const EnumName<E> (&table)[N], const std::string& value, E& out) {
  for (const EnumName<E>& e : table)
    if (value == e.name) {
      out = e.value;
      return true;
    }
  return false;
}

// The names of a table, in its order, for enumNameList and failEnum.
template <class E, std::size_t N>
struct EnumNames {
  explicit EnumNames(const EnumName<E> (&table)[N]) {
    for (std::size_t i = 0; i < N; ++i) names[i] = table[i].name;
  }
  const char* names[N];
};

// The value named by `value` (the string found at `key` of `o`), or one error line.
template <class E, std::size_t N>
E readEnum(const JsonReader& o, const std::string& key, const std::string& value,
           const EnumName<E> (&table)[N], EnumWording wording) {
  E out{};
  if (findEnum(table, value, out)) return out;
  failEnum(o, key, value, EnumNames<E, N>(table).names, N, wording);
}

}  // namespace clhair
