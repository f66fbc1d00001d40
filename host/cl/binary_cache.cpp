// binary_cache.cpp — see binary_cache.h.
#include "cl/binary_cache.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

namespace clhair {

namespace fs = std::filesystem;

namespace {

std::string defaultFolder() {
  if (const char* v = std::getenv("CLHAIR_CACHE_DIR"); v && *v) return v;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::string(x) + "/clhair";
  if (const char* h = std::getenv("HOME"); h && *h) return std::string(h) + "/.cache/clhair";
  return {};
}

// Two independent 64-bit FNV-1a streams (different offsets) over the same bytes.
std::string digest(const std::string& text) {
  std::uint64_t a = 1469598103934665603ull, b = 0x84222325cbf29ce4ull;
  for (unsigned char c : text) {
    a = (a ^ c) * 1099511628211ull;
    b = (b ^ static_cast<unsigned char>(c + 0x5b)) * 1099511628211ull;
  }
  char out[33];
  std::snprintf(out, sizeof out, "%016llx%016llx", static_cast<unsigned long long>(a),
                static_cast<unsigned long long>(b));
  return out;
}

}  // namespace

BinaryCache::BinaryCache(std::string folder) {
  if (folder.empty()) folder = defaultFolder();
  folder_ = folder == "off" ? std::string() : folder;
}

std::string BinaryCache::key(const std::string& platform, const std::string& device,
                             const std::string& driver, const std::string& options,
                             const std::string& source) {
  std::string all;
  for (const std::string* s : {&platform, &device, &driver, &options, &source}) {
    all += std::to_string(s->size());
    all += ':';
    all += *s;
  }
  return digest(all) + ".clbin";
}

std::string BinaryCache::dataKey(const std::string& kind, const std::string& platform,
                                 const std::string& device, const std::string& driver,
                                 const std::string& inputs) {
  std::string k = key(platform, device, driver, kind, inputs);
  return k.substr(0, k.size() - std::string(".clbin").size()) + "." + kind;
}

bool BinaryCache::cacheablePlatform(const std::string& platformName) {
  return platformName.find("Oclgrind") == std::string::npos;
}

std::optional<std::vector<unsigned char>> BinaryCache::load(const std::string& key) const {
  if (!enabled()) return std::nullopt;
  std::ifstream in(fs::path(folder_) / key, std::ios::binary);
  if (!in) return std::nullopt;
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                   std::istreambuf_iterator<char>());
  if (bytes.empty()) return std::nullopt;
  return bytes;
}

void BinaryCache::store(const std::string& key, const std::vector<unsigned char>& binary) const {
  if (!enabled() || binary.empty()) return;
  std::error_code ec;
  fs::create_directories(folder_, ec);
  if (ec) return;
  std::random_device rd;
  const fs::path tmp = fs::path(folder_) / (key + ".tmp" + std::to_string(rd()));
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) return;
    out.write(reinterpret_cast<const char*>(binary.data()),
              static_cast<std::streamsize>(binary.size()));
    if (!out) {
      out.close();
      fs::remove(tmp, ec);
      return;
    }
  }
  fs::rename(tmp, fs::path(folder_) / key, ec);
  if (ec) fs::remove(tmp, ec);
}

}  // namespace clhair
