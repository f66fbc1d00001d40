// regular_file.h — the one way clhair opens a file to read.
//
// A FIFO, a device, a socket or a folder is refused before it is opened (a FIFO blocks, and
// /dev/zero never ends); the file is then opened without blocking and what was opened is
// checked again, so a path swapped in between is refused too. Every reader (JSON, binary
// formats, images, OBJ meshes, kernel sources, cache entries) thus sees a regular file whose
// size is known before the first byte is read.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace clhair {

class RegularFile {
 public:
  // `kind` names the file's role in errors ("scene", "background image"): every failure is
  // one clhair::Error line "<path>: ..." naming it.
  RegularFile(const std::string& path, const std::string& kind);
  ~RegularFile();
  RegularFile(const RegularFile&) = delete;
  RegularFile& operator=(const RegularFile&) = delete;

  const std::string& path() const { return path_; }
  std::uint64_t size() const { return size_; }
  // Reads exactly n bytes at the current position; a short read (the file shrank while being
  // read) is an Error naming `what`.
  void read(void* dst, std::size_t n, const std::string& what);
  // Moves to an absolute byte offset.
  void seek(std::uint64_t offset, const std::string& what);
  // The whole file, when it holds at most `limit` bytes (else an Error naming both sizes).
  std::string readAll(std::uint64_t limit);

 private:
  std::string path_, kind_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

// What a st_mode that is not a regular file names: "a folder", "a FIFO", "a device", ...
const char* fileTypeName(unsigned int mode);

// Whether `path` names an existing regular file (following links); false for FIFOs, devices,
// sockets, folders and missing paths. Opens nothing.
bool isRegularFile(const std::string& path);

}  // namespace clhair
