// safe_write.h — the one way clhair puts a file on disk.
//
// writeFileAtomically writes bytes already in memory (AtomicFile, below, bytes made in pieces) to a
// temporary in the target's folder, checks every write, the size on disk and the first bytes
// read back, flushes the file to disk, closes it (checked), renames it over the target and
// flushes the folder. On any failure the temporary is removed, an existing target is left as
// it was, and one clhair::Error line names the target and the cause ("no space left on
// device"). Temporaries have short names, ".tmp-HHHHHHHH-K": HHHHHHHH hashes the target's
// file name (so a 255-byte name still has room), K is a slot 0..15; a writer holds an flock on
// its temporary until the rename, so a temporary nobody holds was left by a killed run and is
// removed by the next write of the same target (or removeStaleTemporaries). Safe to call from
// several threads at once on different paths.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace clhair {

// Writes `size` bytes to `path` as described above; throws clhair::Error on any failure.
void writeFileAtomically(const std::string& path, const void* data, std::size_t size);

struct AtomicFileState;

// The same write for a file produced in pieces (a streaming encoder, which may also go back
// to fill in a table): the temporary is made on construction, every write is checked as it
// happens, and commit() does the rest (flush, size and first bytes read back against what
// was written, close, rename, folder flush). Destroyed without commit() (an encoder's
// failure, an exception), the temporary is removed and an existing target stays as it was.
class AtomicFile {
 public:
  explicit AtomicFile(const std::string& path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  // n bytes at `offset` (the file grows as needed).
  void write(const void* data, std::size_t n, std::uint64_t offset);
  // Up to n bytes from `offset`: the count read.
  std::size_t read(void* data, std::size_t n, std::uint64_t offset) const;
  // One past the last byte written.
  std::uint64_t size() const;
  void commit();

 private:
  std::unique_ptr<AtomicFileState> s_;
};
inline void writeFileAtomically(const std::string& path, const std::string& bytes) {
  writeFileAtomically(path, bytes.data(), bytes.size());
}

// Removes the temporaries of `path` that no live writer holds (left by killed runs); returns
// how many it removed. Never throws.
std::size_t removeStaleTemporaries(const std::string& path);

// True when `name` (a file name, no folder) has the form of a temporary of writeFileAtomically.
bool isWriteTemporaryName(const std::string& name);

// Refuses, before any work, an output path whose folder does not exist or is not a folder, or
// that names something other than a regular file (a folder, a device, a FIFO): one
// clhair::Error line naming the path.
void checkOutputPath(const std::string& path);

// The text of an errno value as clhair's messages show it: "no space left on device".
std::string errnoText(int error);

}  // namespace clhair
