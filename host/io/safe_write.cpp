// safe_write.cpp — see safe_write.h. POSIX calls throughout: every one is checked, and the
// order is the one that keeps an existing target whole whatever fails (write, fsync, size and
// read-back check, close, rename, fsync of the folder).
#include "io/safe_write.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <type_traits>

#include "clhair/error.h"
#include "io/regular_file.h"

namespace clhair {

namespace {

constexpr int kSlots = 16;                    // concurrent writers of one target
constexpr std::size_t kReadBackBytes = 4096;  // the header compared after the flush
constexpr char kTmpPrefix[] = ".tmp-";

// The folder part of `path` ("." when it has none).
std::string folderOf(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

std::string fileNameOf(const std::string& path) {
  return std::filesystem::path(path).filename().string();
}

// 32-bit FNV-1a of the target's file name: temporaries of one target share it.
std::string nameHash(const std::string& name) {
  std::uint32_t h = 2166136261u;
  for (unsigned char c : name) h = (h ^ c) * 16777619u;
  char buf[9];
  std::snprintf(buf, sizeof(buf), "%08x", h);
  return buf;
}

std::string slotPath(const std::string& folder, const std::string& hash, int slot) {
  return folder + "/" + kTmpPrefix + hash + "-" + std::to_string(slot);
}

// Removes the temporary at `tmp` when no live writer holds it: true when it is gone.
bool removeIfStale(const std::string& tmp) {
  const int fd = ::open(tmp.c_str(), O_RDONLY | O_NONBLOCK | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return errno == ENOENT;
  bool removed = false;
  struct stat opened {};
  struct stat named {};
  // a writer holds its lock from creation to rename; one we can take is a killed run's
  if (::flock(fd, LOCK_EX | LOCK_NB) == 0 && ::fstat(fd, &opened) == 0 && S_ISREG(opened.st_mode) &&
      ::lstat(tmp.c_str(), &named) == 0 && named.st_ino == opened.st_ino &&
      named.st_dev == opened.st_dev)
    removed = ::unlink(tmp.c_str()) == 0;
  ::close(fd);
  return removed;
}

}  // namespace

// The open temporary of one write: removed (with its lock released) unless committed.
class WriteTemporary {
 public:
  WriteTemporary(const std::string& target, const std::string& folder) : target_(target) {
    const std::string hash = nameHash(fileNameOf(target));
    int restarts = 0;
    for (int slot = 0; slot < kSlots && fd_ < 0; ++slot) {
      const std::string tmp = slotPath(folder, hash, slot);
      for (int attempt = 0; attempt < 2 && fd_ < 0; ++attempt) {
        fd_ = ::open(tmp.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd_ >= 0) {
          path_ = tmp;
          break;
        }
        if (errno != EEXIST)
          throw Error(target + ": cannot create a file in " + folder + " (" + errnoText(errno) +
                      ")");
        if (!removeIfStale(tmp)) break;  // a live writer's: the next slot
      }
      if (fd_ < 0) continue;
      // The lock marks the temporary as live. A cleaner that opened the name between our
      // create and this lock may have removed it: then start again on a fresh name.
      // (Removed before our open, the name is gone: the same as a removal after it.)
      lock_ = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
      struct stat opened {};
      struct stat named {};
      const bool held = lock_ >= 0 && ::flock(lock_, LOCK_EX) == 0 && ::fstat(fd_, &opened) == 0 &&
                        ::lstat(path_.c_str(), &named) == 0 && named.st_ino == opened.st_ino &&
                        named.st_dev == opened.st_dev;
      if (!held) {
        ::close(fd_);
        if (lock_ >= 0) ::close(lock_);
        fd_ = lock_ = -1;
        path_.clear();
        if (++restarts < kSlots * 4) --slot;  // the same slot again: it is free now
      }
    }
    if (fd_ < 0)
      throw Error(target + ": " + std::to_string(kSlots) +
                  " other writes of this file are in progress in " + folder);
  }

  ~WriteTemporary() {
    if (fd_ >= 0) ::close(fd_);
    if (!committed_ && !path_.empty()) ::unlink(path_.c_str());
    if (lock_ >= 0) ::close(lock_);
  }

  WriteTemporary(const WriteTemporary&) = delete;
  WriteTemporary& operator=(const WriteTemporary&) = delete;

  int fd() const { return fd_; }
  const std::string& path() const { return path_; }

  // Closes the write descriptor, checked (the lock stays held until the destructor).
  void close() {
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0 && errno != EINTR)
      throw Error(target_ + ": closing the written file failed (" + errnoText(errno) + ")");
  }

  void commit() { committed_ = true; }

 private:
  std::string target_, path_;
  int fd_ = -1, lock_ = -1;
  bool committed_ = false;
};

std::string errnoText(int error) {
  char buf[256];
  // GNU strerror_r returns the text (maybe not in buf); the XSI one fills buf.
  auto pick = [&](auto r) -> const char* {
    if constexpr (std::is_same_v<decltype(r), char*>)
      return r;
    else
      return r == 0 ? buf : "unknown error";
  };
  std::string text = pick(::strerror_r(error, buf, sizeof(buf)));
  if (!text.empty() && std::isupper(static_cast<unsigned char>(text[0])) &&
      (text.size() < 2 || !std::isupper(static_cast<unsigned char>(text[1]))))
    text[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(text[0])));
  return text;
}

bool isWriteTemporaryName(const std::string& name) {
  // ".tmp-" + 8 hex digits + "-" + slot
  if (name.rfind(kTmpPrefix, 0) != 0 || name.size() < 15 || name.size() > 16 || name[13] != '-')
    return false;
  for (std::size_t i = 5; i < 13; ++i)
    if (!std::isxdigit(static_cast<unsigned char>(name[i]))) return false;
  for (std::size_t i = 14; i < name.size(); ++i)
    if (!std::isdigit(static_cast<unsigned char>(name[i]))) return false;
  return true;
}

std::size_t removeStaleTemporaries(const std::string& path) {
  const std::string folder = folderOf(path), hash = nameHash(fileNameOf(path));
  std::size_t removed = 0;
  for (int slot = 0; slot < kSlots; ++slot) {
    const std::string tmp = slotPath(folder, hash, slot);
    struct stat st {};
    if (::lstat(tmp.c_str(), &st) != 0) continue;
    removed += removeIfStale(tmp) ? 1 : 0;
  }
  return removed;
}

void checkOutputPath(const std::string& path) {
  if (path.empty()) throw Error("an empty output file name");
  const std::string name = fileNameOf(path);
  if (name.empty() || name == "." || name == "..")
    throw Error(path + ": names a folder, expected a file name");
  if (name.size() > 255)
    throw Error(path + ": the file name has " + std::to_string(name.size()) +
                " bytes, at most 255 are allowed");
  const std::string folder = folderOf(path);
  struct stat st {};
  if (::stat(folder.c_str(), &st) != 0)
    throw Error(path + ": cannot write into " + folder + " (" + errnoText(errno) + ")");
  if (!S_ISDIR(st.st_mode)) throw Error(path + ": " + folder + " is not a folder");
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    throw Error(path + ": is " + fileTypeName(st.st_mode) + ", not a file clhair can replace");
}

struct AtomicFileState {
  AtomicFileState(const std::string& target, const std::string& dir)
      : path(target), folder(dir), tmp(target, dir) {}
  std::string path, folder;
  WriteTemporary tmp;
  std::uint64_t size = 0;
  unsigned char head[kReadBackBytes] = {};  // the first bytes as written, for the read-back
};

namespace {

std::string preparedFolder(const std::string& path) {
  checkOutputPath(path);
  removeStaleTemporaries(path);
  return folderOf(path);
}

}  // namespace

AtomicFile::AtomicFile(const std::string& path)
    : s_(std::make_unique<AtomicFileState>(path, preparedFolder(path))) {}

AtomicFile::~AtomicFile() = default;

std::uint64_t AtomicFile::size() const { return s_->size; }

void AtomicFile::write(const void* data, std::size_t n, std::uint64_t offset) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  std::size_t done = 0;
  while (done < n) {
    const ssize_t k =
        ::pwrite(s_->tmp.fd(), bytes + done, std::min<std::size_t>(n - done, 1u << 30),
                 static_cast<off_t>(offset + done));
    const int e = k < 0 ? errno : EIO;
    if (k < 0 && e == EINTR) continue;
    if (k <= 0)
      throw Error(s_->path + ": writing failed after " +
                  std::to_string(std::max<std::uint64_t>(s_->size, offset + done)) + " bytes (" +
                  errnoText(e) + ")");
    done += static_cast<std::size_t>(k);
  }
  if (offset < kReadBackBytes)
    std::memcpy(s_->head + offset, bytes, std::min<std::uint64_t>(n, kReadBackBytes - offset));
  s_->size = std::max<std::uint64_t>(s_->size, offset + n);
}

std::size_t AtomicFile::read(void* data, std::size_t n, std::uint64_t offset) const {
  const ssize_t k = ::pread(s_->tmp.fd(), data, n, static_cast<off_t>(offset));
  if (k < 0)
    throw Error(s_->path + ": reading back the file being written failed (" + errnoText(errno) +
                ")");
  return static_cast<std::size_t>(k);
}

void AtomicFile::commit() {
  const std::string& path = s_->path;
  WriteTemporary& tmp = s_->tmp;
  const std::uint64_t size = s_->size;
  if (::fsync(tmp.fd()) != 0)
    throw Error(path + ": flushing the file to disk failed (" + errnoText(errno) + ")");
  struct stat st {};
  if (::fstat(tmp.fd(), &st) != 0)
    throw Error(path + ": cannot check the written file (" + errnoText(errno) + ")");
  if (static_cast<std::uint64_t>(st.st_size) != size)
    throw Error(path + ": the written file holds " + std::to_string(st.st_size) +
                " bytes, expected " + std::to_string(size));
  const std::size_t head = static_cast<std::size_t>(std::min<std::uint64_t>(size, kReadBackBytes));
  if (head > 0) {
    unsigned char back[kReadBackBytes];
    const ssize_t k = ::pread(tmp.fd(), back, head, 0);
    if (k != static_cast<ssize_t>(head) || std::memcmp(back, s_->head, head) != 0)
      throw Error(path + ": the written file does not read back as written" +
                  (k < 0 ? " (" + errnoText(errno) + ")" : std::string()));
  }
  tmp.close();
  if (::rename(tmp.path().c_str(), path.c_str()) != 0)
    throw Error(path + ": cannot move the finished file into place (" + errnoText(errno) + ")");
  tmp.commit();
  // the rename itself is durable only once the folder is flushed; folders that cannot be
  // flushed (EINVAL: some network and FUSE file systems) hold it as well as they can
  const int dir = ::open(s_->folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    const int r = ::fsync(dir);
    const int e = errno;
    ::close(dir);
    if (r != 0 && e != EINVAL && e != ENOTSUP && e != EBADF)
      throw Error(path + ": written, but flushing its folder to disk failed (" + errnoText(e) +
                  ")");
  }
}

void writeFileAtomically(const std::string& path, const void* data, std::size_t size) {
  AtomicFile f(path);
  f.write(data, size, 0);
  f.commit();
}

}  // namespace clhair
