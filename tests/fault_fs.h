// fault_fs.h — folders where writing fails, for the fault-injection tests.
//
// FullFolder: writes fail with "no space left on device". As root it is a real full file system:
// a 256 KiB tmpfs mounted on the folder and filled to the last page; otherwise (or when mount
// is refused) an ordinary folder whose writes the preload shim (fault_shim.c) fails, for the
// child processes started with shimEnv(). ReadOnlyFolder: writes fail with "read-only file
// system" (a tmpfs remounted read-only, as root) or "permission denied" (mode 0555). Both hold
// the files given at construction (existing targets) and undo themselves when destroyed.
#pragma once

#include <sys/mount.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "io/safe_write.h"
#include "test_util.h"

namespace clhair::test {

inline std::string faultShimPath() { return envOr("CLHAIR_FAULT_SHIM", CLHAIR_TEST_FAULT_SHIM); }
inline std::string writeProbePath() { return envOr("CLHAIR_WRITE_PROBE", CLHAIR_TEST_WRITE_PROBE); }

// The environment assignments that load the fault shim into a command (plus `settings`).
inline std::string shimEnv(const std::string& settings) {
  return "env LD_PRELOAD=" + quote(faultShimPath()) +
         " ASAN_OPTIONS=verify_asan_link_order=0:detect_leaks=0 " + settings + " ";
}

// The names in `dir` (hidden ones too).
inline std::vector<std::string> listFolder(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec))
    out.push_back(e.path().filename().string());
  return out;
}

// The temporaries of clhair's writer in `dir` (and of older releases: ".tmp-" prefixes).
inline std::vector<std::string> temporariesIn(const std::string& dir) {
  std::vector<std::string> out;
  for (const std::string& n : listFolder(dir))
    if (isWriteTemporaryName(n) || n.rfind(".tmp-", 0) == 0 || n.find(".tmp-") != std::string::npos)
      out.push_back(n);
  return out;
}

inline bool isMountPoint(const std::string& dir) {
  struct stat a {};
  struct stat b {};
  return ::stat(dir.c_str(), &a) == 0 && ::stat((dir + "/..").c_str(), &b) == 0 &&
         a.st_dev != b.st_dev;
}

// A tmpfs of `bytes` on `dir` (root only); false when it cannot be mounted.
inline bool mountTmpfs(const std::string& dir, std::size_t bytes) {
  if (::geteuid() != 0) return false;
  if (isMountPoint(dir)) ::umount2(dir.c_str(), MNT_DETACH);  // a crashed run's
  return ::mount("tmpfs", dir.c_str(), "tmpfs", 0, ("size=" + std::to_string(bytes)).c_str()) == 0;
}

class FullFolder {
 public:
  FullFolder(const std::string& dir, const std::map<std::string, std::string>& files = {},
             bool forceShim = false)
      : dir_(dir) {
    std::filesystem::create_directories(dir);
    tmpfs_ = !forceShim && mountTmpfs(dir, 256 << 10);
    for (const auto& [name, bytes] : files) writeBytes(dir + "/" + name, bytes);
    if (!tmpfs_) return;
    // fill it: a filler file grown until the file system refuses, then byte by byte
    std::FILE* f = std::fopen((dir + "/filler").c_str(), "wb");
    std::vector<char> block(4096, 'f');
    while (f && std::fwrite(block.data(), 1, block.size(), f) == block.size() &&
           std::fflush(f) == 0) {
    }
    if (f) std::fclose(f);
  }
  ~FullFolder() {
    if (tmpfs_) ::umount2(dir_.c_str(), MNT_DETACH);
  }
  FullFolder(const FullFolder&) = delete;
  FullFolder& operator=(const FullFolder&) = delete;

  bool tmpfs() const { return tmpfs_; }
  // What a command writing here needs before it: nothing on a real full file system, the shim
  // otherwise.
  std::string env() const {
    return tmpfs_ ? std::string() : shimEnv("CLHAIR_FAULT_FULL_DIR=" + quote(absolute()));
  }
  std::string absolute() const { return std::filesystem::canonical(dir_).string(); }
  // The cause a failed write names.
  static std::string cause() { return "no space left on device"; }

 private:
  std::string dir_;
  bool tmpfs_ = false;
};

class ReadOnlyFolder {
 public:
  ReadOnlyFolder(const std::string& dir, const std::map<std::string, std::string>& files = {})
      : dir_(dir) {
    std::filesystem::create_directories(dir);
    tmpfs_ = mountTmpfs(dir, 256 << 10);
    for (const auto& [name, bytes] : files) writeBytes(dir + "/" + name, bytes);
    if (tmpfs_)
      ::mount("tmpfs", dir.c_str(), "tmpfs", MS_REMOUNT | MS_RDONLY, nullptr);
    else
      ::chmod(dir.c_str(), 0555);
  }
  ~ReadOnlyFolder() {
    if (tmpfs_)
      ::umount2(dir_.c_str(), MNT_DETACH);
    else
      ::chmod(dir_.c_str(), 0755);
  }
  ReadOnlyFolder(const ReadOnlyFolder&) = delete;
  ReadOnlyFolder& operator=(const ReadOnlyFolder&) = delete;

  bool tmpfs() const { return tmpfs_; }
  std::string cause() const { return tmpfs_ ? "read-only file system" : "permission denied"; }

 private:
  std::string dir_;
  bool tmpfs_ = false;
};

}  // namespace clhair::test
