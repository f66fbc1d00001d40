// json_util.cpp — strict JSON getters, file reading with positions, atomic writes (safe_write.h).
#include "io/json_util.h"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "clhair/error.h"
#include "io/regular_file.h"
#include "io/safe_write.h"

namespace clhair {

using nlohmann::json;

namespace {
std::string showNumber(double v) {
  std::ostringstream ss;
  ss << v;
  return ss.str();
}
}  // namespace

JsonReader::JsonReader(std::string file, const json& object, std::string prefix)
    : file_(std::move(file)), obj_(&object), prefix_(std::move(prefix)) {
  if (!object.is_object())
    throw Error(file_ + ": " + (prefix_.empty() ? std::string("top level") : prefix_) +
                ": must be a JSON object");
}

void JsonReader::fail(const std::string& key, const std::string& what) const {
  throw Error(file_ + ": " + path(key) + ": " + what);
}

const json& JsonReader::require(const std::string& key) const {
  if (!obj_->contains(key)) fail(key, "is missing");
  return (*obj_)[key];
}

double JsonReader::number(const std::string& key, double def, double lo, double hi) const {
  if (!obj_->contains(key)) return def;
  const json& v = (*obj_)[key];
  if (!v.is_number()) fail(key, "must be a number");
  double d = v.get<double>();
  if (!std::isfinite(d)) fail(key, "is not a finite number");
  if (d < lo || d > hi)
    fail(key, "is " + showNumber(d) + ", expected " + showNumber(lo) + ".." + showNumber(hi));
  return d;
}

long long JsonReader::integer64(const std::string& key, long long def, long long lo,
                                long long hi) const {
  if (!obj_->contains(key)) return def;
  const json& v = (*obj_)[key];
  if (!v.is_number_integer()) {
    if (v.is_number_float()) fail(key, "must be a whole number");
    fail(key, "must be an integer");
  }
  long long x =
      v.is_number_unsigned() && v.get<unsigned long long>() > static_cast<unsigned long long>(hi)
          ? hi + 1
          : v.get<long long>();
  if (x < lo || x > hi)
    fail(key, "is " + v.dump() + ", expected " + std::to_string(lo) + ".." + std::to_string(hi));
  return x;
}

int JsonReader::integer(const std::string& key, int def, int lo, int hi) const {
  return static_cast<int>(integer64(key, def, lo, hi));
}

bool JsonReader::boolean(const std::string& key, bool def) const {
  if (!obj_->contains(key)) return def;
  const json& v = (*obj_)[key];
  if (!v.is_boolean()) fail(key, "must be true or false");
  return v.get<bool>();
}

std::string JsonReader::string(const std::string& key, const std::string& def) const {
  if (!obj_->contains(key)) return def;
  const json& v = (*obj_)[key];
  if (!v.is_string()) fail(key, "must be a string");
  return v.get<std::string>();
}

glm::vec3 JsonReader::vec3(const std::string& key, const glm::vec3& def, double lo,
                           double hi) const {
  if (!obj_->contains(key)) return def;
  const json& v = (*obj_)[key];
  if (!v.is_array() || v.size() != 3) fail(key, "must be an array of 3 numbers");
  glm::vec3 out;
  for (int i = 0; i < 3; ++i) {
    if (!v[i].is_number()) fail(key, "must be an array of 3 numbers");
    double d = v[i].get<double>();
    if (!std::isfinite(d)) fail(key, "holds a non-finite number");
    if (d < lo || d > hi)
      fail(key, "component " + std::to_string(i) + " is " + showNumber(d) + ", expected " +
                    showNumber(lo) + ".." + showNumber(hi));
    out[i] = static_cast<float>(d);
  }
  return out;
}

JsonReader JsonReader::object(const json& j, const std::string& key) const {
  if (!j.is_object()) fail(key, "must be a JSON object");
  return JsonReader(file_, j, path(key));
}

void JsonReader::rejectUnknown(std::initializer_list<const char*> known) const {
  rejectUnknown(std::vector<std::string>(known.begin(), known.end()));
}

void JsonReader::rejectUnknown(const std::vector<std::string>& known) const {
  for (auto it = obj_->begin(); it != obj_->end(); ++it) {
    bool ok = false;
    for (const std::string& k : known) ok |= it.key() == k;
    if (!ok) {
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      fail(it.key(), "is not a known key (known: " + list + ")");
    }
  }
}

json readJsonFile(const std::string& path, const std::string& what) {
  // a device or FIFO (/dev/zero, /dev/stdin) would be read forever or block: refused unopened
  RegularFile file(path, what);
  const std::string text = file.readAll(~std::uint64_t(0));
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    std::size_t line = 1, col = 1;
    for (std::size_t i = 0; i + 1 < e.byte && i < text.size(); ++i) {
      if (text[i] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    std::string msg = e.what();
    auto pos = msg.find("parse error");
    throw Error(path + ":" + std::to_string(line) + ":" + std::to_string(col) + ": malformed " +
                what + " JSON: " + (pos == std::string::npos ? msg : msg.substr(pos)));
  } catch (const json::exception& e) {
    // out_of_range 406: a number beyond double range such as 1e400; no position is known.
    throw Error(path + ": malformed " + what + " JSON: " + e.what());
  }
}

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

void writeTextAtomically(const std::string& path, const std::string& text) {
  writeFileAtomically(path, text);
}

}  // namespace clhair
