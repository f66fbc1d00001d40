// enum_field.cpp — the messages of the table-driven enum check (io/enum_field.h): the
// allowed names joined with commas and a final "or", quoted as the scene format quotes them.
#include "io/enum_field.h"

namespace clhair {

std::string enumNameList(const char* const* names, std::size_t count, bool quoted) {
  const std::string q = quoted ? "\"" : "";
  std::string out;
  for (std::size_t i = 0; i < count; ++i) {
    if (i > 0) out += i + 1 == count ? " or " : ", ";
    out += q + names[i] + q;
  }
  return out;
}

void failEnum(const JsonReader& o, const std::string& key, const std::string& value,
              const char* const* names, std::size_t count, EnumWording wording) {
  const std::string list = enumNameList(names, count, true);
  if (wording == EnumWording::Expected) o.fail(key, "is \"" + value + "\", expected " + list);
  o.fail(key, "must be " + list + ", not \"" + value + "\"");
}

}  // namespace clhair
