// safe_write.h — the one way clhair puts a file on disk.
//
// writeFileAtomically writes bytes already in memory (images are encoded in memory first) to a
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
#include <string>

namespace clhair {

// Writes `size` bytes to `path` as described above; throws clhair::Error on any failure.
void writeFileAtomically(const std::string& path, const void* data, std::size_t size);
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
