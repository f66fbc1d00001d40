// binary_cache.cpp — see binary_cache.h: keys, the entry file format and the healing load.
#include "cl/binary_cache.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "clhair/error.h"
#include "io/regular_file.h"
#include "io/safe_write.h"

namespace clhair {

namespace fs = std::filesystem;

namespace {

constexpr char kMagic[9] = "CLHCACH2";
constexpr std::uint32_t kEntryVersion = 1;
constexpr std::size_t kHeaderBytes = 40;
constexpr std::uint64_t kMaxKeyBytes = 1024;
constexpr std::uint64_t kMaxEntryBytes = std::uint64_t(1) << 30;
constexpr const char* kEntryFolder = "v2";

std::uint64_t fnv64(const unsigned char* p, std::size_t n) {
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

void appendLe(std::string& out, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFFu));
}

std::uint64_t loadLe(const unsigned char* p, int bytes) {
  std::uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = v << 8 | p[i];
  return v;
}

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

std::string BinaryCache::hostBuild() {
#ifdef CLHAIR_BUILD_ID
  return CLHAIR_BUILD_ID;
#else
  return "unknown build";
#endif
}

std::string BinaryCache::dataKey(const std::string& kind, const std::string& platform,
                                 const std::string& device, const std::string& driver,
                                 const std::string& inputs, const std::string& build) {
  std::string k = key(platform, device, driver, kind + "|" + build, inputs);
  return k.substr(0, k.size() - std::string(".clbin").size()) + "." + kind;
}

bool BinaryCache::cacheablePlatform(const std::string& platformName) {
  return platformName.find("Oclgrind") == std::string::npos;
}

bool BinaryCache::driverKeepsPrograms(const std::string& platformName) {
  if (platformName.find("Portable Computing Language") == std::string::npos) return false;
  const char* v = std::getenv("POCL_KERNEL_CACHE");
  return !(v && std::string(v) == "0");
}

std::string BinaryCache::entryPath(const std::string& key) const {
  return (fs::path(folder_) / kEntryFolder / key).string();
}

std::optional<std::vector<unsigned char>> BinaryCache::load(const std::string& key) const {
  if (!enabled()) return std::nullopt;
  const std::string path = entryPath(key);
  struct stat named {};
  if (::lstat(path.c_str(), &named) != 0) return std::nullopt;  // no entry
  std::string bytes;
  bool readable = false;
  try {
    RegularFile f(path, "cache entry");
    bytes = f.readAll(kMaxEntryBytes);
    readable = true;
  } catch (const Error&) {
  }
  if (readable)
    if (auto payload = decodeCacheEntry(bytes, key)) return payload;
  // Damaged, foreign or unreadable: remove it (unless a writer has just replaced it with a
  // fresh entry) so that the rebuilt program takes its place.
  struct stat now {};
  if (::lstat(path.c_str(), &now) == 0 && now.st_ino == named.st_ino &&
      now.st_dev == named.st_dev && now.st_mtime == named.st_mtime)
    ::unlink(path.c_str());
  return std::nullopt;
}

bool BinaryCache::writable() const {
  if (!enabled()) return false;
  std::error_code ec;
  fs::create_directories(fs::path(folder_) / kEntryFolder, ec);
  if (ec) return false;
  const std::string probe = (fs::path(folder_) / kEntryFolder /
                             (".probe-" + std::to_string(static_cast<long>(::getpid()))))
                                .string();
  try {
    writeFileAtomically(probe, std::string(4096, '\0'));
  } catch (const Error&) {
    return false;
  }
  ::unlink(probe.c_str());
  return true;
}

void BinaryCache::store(const std::string& key, const std::vector<unsigned char>& binary) const {
  if (!enabled() || binary.empty() || binary.size() > kMaxEntryBytes - 4096) return;
  std::error_code ec;
  fs::create_directories(fs::path(folder_) / kEntryFolder, ec);
  if (ec) return;
  try {
    writeFileAtomically(entryPath(key), encodeCacheEntry(key, binary));
  } catch (const Error&) {  // a full disk or a read-only folder: no cache, nothing else
  }
}

namespace {

std::string payloadStamp(const std::vector<unsigned char>& payload) {
  char out[32];
  std::snprintf(out, sizeof out, "%016llx %llu",
                static_cast<unsigned long long>(fnv64(payload.data(), payload.size())),
                static_cast<unsigned long long>(payload.size()));
  return out;
}

}  // namespace

bool BinaryCache::proven(const std::string& key, const std::vector<unsigned char>& payload) const {
  if (!enabled()) return false;
  try {
    RegularFile f(entryPath(key) + ".proven", "cache stamp");
    return f.readAll(64) == payloadStamp(payload);
  } catch (const Error&) {
    return false;
  }
}

void BinaryCache::markProven(const std::string& key,
                             const std::vector<unsigned char>& payload) const {
  if (!enabled()) return;
  const std::string stamp = entryPath(key) + ".proven";
  struct stat st {};
  if (::lstat(stamp.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    ::unlink(stamp.c_str());  // a FIFO or a folder where the stamp belongs: replaced
  try {
    writeFileAtomically(stamp, payloadStamp(payload));
  } catch (const Error&) {  // no stamp: the entry is proven again next time
  }
}

void BinaryCache::remove(const std::string& key) const {
  if (!enabled()) return;
  ::unlink(entryPath(key).c_str());
  ::unlink((entryPath(key) + ".proven").c_str());
}

std::string encodeCacheEntry(const std::string& key, const std::vector<unsigned char>& payload) {
  std::string out(kMagic, 8);
  appendLe(out, kEntryVersion, 4);
  appendLe(out, key.size(), 4);
  appendLe(out, payload.size(), 8);
  appendLe(out, fnv64(payload.data(), payload.size()), 8);
  std::string head = out + key;
  appendLe(out, fnv64(reinterpret_cast<const unsigned char*>(head.data()), head.size()), 8);
  out += key;
  out.append(reinterpret_cast<const char*>(payload.data()), payload.size());
  return out;
}

std::optional<std::vector<unsigned char>> decodeCacheEntry(const std::string& bytes,
                                                           const std::string& key,
                                                           std::string* why) {
  auto refuse = [&](const char* reason) -> std::optional<std::vector<unsigned char>> {
    if (why) *why = reason;
    return std::nullopt;
  };
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  if (bytes.size() < kHeaderBytes) return refuse("shorter than the header");
  if (std::memcmp(p, kMagic, 8) != 0) return refuse("not an entry (magic)");
  if (loadLe(p + 8, 4) != kEntryVersion) return refuse("another entry version");
  const std::uint64_t keyBytes = loadLe(p + 12, 4), payloadBytes = loadLe(p + 16, 8);
  if (keyBytes > kMaxKeyBytes) return refuse("a key longer than any");
  if (payloadBytes > bytes.size() || bytes.size() - kHeaderBytes - keyBytes != payloadBytes ||
      bytes.size() < kHeaderBytes + keyBytes)
    return refuse("its size does not match its header (truncated?)");
  std::string head = bytes.substr(0, 32) + bytes.substr(kHeaderBytes, keyBytes);
  if (fnv64(reinterpret_cast<const unsigned char*>(head.data()), head.size()) != loadLe(p + 32, 8))
    return refuse("the header checksum does not match");
  if (bytes.compare(kHeaderBytes, keyBytes, key) != 0 || keyBytes != key.size())
    return refuse("another key's entry");
  const unsigned char* payload = p + kHeaderBytes + keyBytes;
  if (fnv64(payload, payloadBytes) != loadLe(p + 24, 8))
    return refuse("the payload checksum does not match");
  return std::vector<unsigned char>(payload, payload + payloadBytes);
}

}  // namespace clhair
