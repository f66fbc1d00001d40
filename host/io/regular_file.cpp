// regular_file.cpp — see regular_file.h.
#include "io/regular_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

#include "clhair/error.h"
#include "io/safe_write.h"

namespace clhair {

const char* fileTypeName(unsigned int mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

bool isRegularFile(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

RegularFile::RegularFile(const std::string& path, const std::string& kind)
    : path_(path), kind_(kind) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw Error(path + ": cannot open " + kind + " file (" + errnoText(errno) + ")");
  if (!S_ISREG(st.st_mode))
    throw Error(path + ": is not a regular file (" + fileTypeName(st.st_mode) + "); " + kind +
                " files must be regular files");
  // O_NONBLOCK: should the path have become a FIFO since the check, opening it returns at once
  fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (fd_ < 0) throw Error(path + ": cannot open " + kind + " file (" + errnoText(errno) + ")");
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd_);
    fd_ = -1;
    throw Error(path + ": is not a regular file; " + kind + " files must be regular files");
  }
  // reads of a regular file never block; clear the flag anyway for plain semantics
  const int flags = ::fcntl(fd_, F_GETFL);
  if (flags >= 0) ::fcntl(fd_, F_SETFL, flags & ~O_NONBLOCK);
  size_ = static_cast<std::uint64_t>(st.st_size);
}

RegularFile::~RegularFile() {
  if (fd_ >= 0) ::close(fd_);
}

void RegularFile::read(void* dst, std::size_t n, const std::string& what) {
  auto* p = static_cast<unsigned char*>(dst);
  std::size_t done = 0;
  while (done < n) {
    const ssize_t k = ::read(fd_, p + done, std::min<std::size_t>(n - done, 1u << 30));
    if (k < 0 && errno == EINTR) continue;
    if (k < 0)
      throw Error(path_ + ": reading " + what + " of the " + kind_ + " file failed (" +
                  errnoText(errno) + ")");
    if (k == 0)
      throw Error(path_ + ": file ended early while reading " + what +
                  " (was it changed while being read?)");
    done += static_cast<std::size_t>(k);
  }
}

void RegularFile::seek(std::uint64_t offset, const std::string& what) {
  if (::lseek(fd_, static_cast<off_t>(offset), SEEK_SET) < 0)
    throw Error(path_ + ": cannot seek to " + what + " at byte " + std::to_string(offset));
}

std::string RegularFile::readAll(std::uint64_t limit) {
  if (size_ > limit)
    throw Error(path_ + ": the " + kind_ + " file has " + std::to_string(size_) +
                " bytes, more than the " + std::to_string(limit) + " this reader accepts");
  std::string out(static_cast<std::size_t>(size_), '\0');
  seek(0, "the start");
  read(out.data(), out.size(), "the file");
  return out;
}

}  // namespace clhair
