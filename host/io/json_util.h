// json_util.h — strict JSON reading with one-line errors that name the file and element.
//
// JsonReader wraps one JSON object: typed getters with defaults and ranges, and a check
// that rejects unknown keys (a typo in a scene should not be silently ignored). Errors look
// like `scene.json: grooms[0].transform.scale: is -1, expected 1e-06..1e+06`.
#pragma once

#include <initializer_list>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

namespace clhair {

class JsonReader {
 public:
  JsonReader(std::string file, const nlohmann::json& object, std::string prefix = {});

  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  bool has(const std::string& key) const { return obj_->contains(key); }
  const nlohmann::json& require(const std::string& key) const;
  double number(const std::string& key, double def, double lo, double hi) const;
  int integer(const std::string& key, int def, int lo, int hi) const;
  long long integer64(const std::string& key, long long def, long long lo, long long hi) const;
  bool boolean(const std::string& key, bool def) const;
  std::string string(const std::string& key, const std::string& def) const;
  glm::vec3 vec3(const std::string& key, const glm::vec3& def, double lo, double hi) const;
  // A reader for the object `j` found under `key` (fails if it is not an object).
  JsonReader object(const nlohmann::json& j, const std::string& key) const;
  void rejectUnknown(std::initializer_list<const char*> known) const;
  void rejectUnknown(const std::vector<std::string>& known) const;
  const std::string& file() const { return file_; }
  std::string path(const std::string& key) const {
    return prefix_.empty() ? key : prefix_ + "." + key;
  }

 private:
  std::string file_;
  const nlohmann::json* obj_;
  std::string prefix_;
};

// Parses a JSON file; a missing file or malformed text becomes one clhair::Error line
// with the file, line and column. `what` names the file's role ("scene", "hair mesh").
nlohmann::json readJsonFile(const std::string& path, const std::string& what);

// Writes text (or any bytes) to `path` through writeFileAtomically (io/safe_write.h).
void writeTextAtomically(const std::string& path, const std::string& text);

// The file name's extension in lower case, with its dot (".hair"), or "" when it has none.
std::string lowerExtension(const std::string& path);

}  // namespace clhair
