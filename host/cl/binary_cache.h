// binary_cache.h — compiled OpenCL programs kept on disk between runs.
//
// Some drivers compile for a long time and keep nothing (Intel's CPU runtime: 40-90 s for
// clhair's kernels on every start); drivers that keep their own (PoCL) are left to it
// (driverKeepsPrograms). After a build the program's binary is stored under a
// key that names everything it depends on — platform, device, driver version, build
// options and the full expanded source text — so any change makes a new entry and a stale
// binary is never used. A binary the driver refuses is ignored (and rebuilt from source), and
// an entry is built in a child process before its first use (cl/cache_proof.h), so a binary
// written wrong under a valid checksum never reaches the renderer's driver.
// Writes go to a temporary file that is renamed into place, so concurrent processes never
// read a half-written entry. The folder is CLHAIR_CACHE_DIR, else $XDG_CACHE_HOME/clhair,
// else ~/.cache/clhair; CLHAIR_CACHE_DIR=off disables the cache. Simulators whose build
// options come from their own environment (Oclgrind: OCLGRIND_BUILD_OPTIONS, which the key
// cannot see) are never cached (cacheablePlatform). The same folder keeps results a device
// computes deterministically from inputs the key can name (dataKey, which also names the host
// build): the ambient-occlusion bake of a hair mesh (host/groom/hair_mesh_gpu.cpp).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace clhair {

class BinaryCache {
 public:
  // folder "" : the default location; "off": no caching.
  explicit BinaryCache(std::string folder = {});

  bool enabled() const { return !folder_.empty(); }
  const std::string& folder() const { return folder_; }
  // The entry's file name for a program (hex digest of every input).
  static std::string key(const std::string& platform, const std::string& device,
                         const std::string& driver, const std::string& options,
                         const std::string& source);
  // The entry's file name for other results computed on a device from `inputs`: `kind`
  // names what it holds and is the file's extension (".ao": a baked ambient occlusion).
  // The key also names the host build (`build`, by default hostBuild()): a result the host
  // helped compute may differ in its last bits between compilers and flags, and a cache
  // folder shared by a Release and a sanitized build must not hand one build's bytes to
  // the other.
  static std::string dataKey(const std::string& kind, const std::string& platform,
                             const std::string& device, const std::string& driver,
                             const std::string& inputs, const std::string& build = hostBuild());
  // This build's compiler, its version, build type, flags and sanitizers (CMakeLists.txt).
  static std::string hostBuild();
  // The payload stored under `key`, or nothing (no entry, or a damaged one, which is removed).
  std::optional<std::vector<unsigned char>> load(const std::string& key) const;
  // The file an entry is stored in.
  std::string entryPath(const std::string& key) const;
  // False for platforms whose builds depend on more than the key holds.
  static bool cacheablePlatform(const std::string& platformName);
  // True for drivers that keep the programs they compile in a cache of their own: PoCL (its
  // kernel cache, unless POCL_KERNEL_CACHE=0). Their programs are not stored here: reading a
  // binary back from PoCL compiles every kernel of the program once more (for any local size)
  // and proving it costs a child process, while a build from source finds PoCL's own entry.
  static bool driverKeepsPrograms(const std::string& platformName);
  // Whether an entry can be written now: a 4 KiB probe file written and removed in the
  // entries' folder (false for a read-only or full file system). A caller that pays to make
  // an entry's bytes (a driver's binary) asks first.
  bool writable() const;
  // Best effort: a cache that cannot be written only costs the next run a compile.
  void store(const std::string& key, const std::vector<unsigned char>& binary) const;
  // Whether the entry `key` holding `payload` was proven (host/cl/cache_proof.h): a stamp
  // beside it ("<entry>.proven") holds the payload's checksum, so a replaced entry is proven
  // again. markProven writes the stamp (best effort); remove deletes the entry and its stamp.
  bool proven(const std::string& key, const std::vector<unsigned char>& payload) const;
  void markProven(const std::string& key, const std::vector<unsigned char>& payload) const;
  void remove(const std::string& key) const;

 private:
  std::string folder_;
};

// An entry file: "CLHCACH2", u32 version, u32 key length, u64 payload length, u64 checksum of
// the payload, u64 checksum of the 32 bytes before it and the key, the key, the payload
// (little endian; checksums: 64-bit FNV-1a).
std::string encodeCacheEntry(const std::string& key, const std::vector<unsigned char>& payload);
// The payload of an entry file's bytes, or nothing when they are not exactly an entry of `key`
// (`why`, when given, says what is wrong). Never throws; any bytes are safe.
std::optional<std::vector<unsigned char>> decodeCacheEntry(const std::string& bytes,
                                                           const std::string& key,
                                                           std::string* why = nullptr);

}  // namespace clhair
