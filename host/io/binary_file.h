// binary_file.h — a regular file opened for reading (io/regular_file.h: FIFOs, devices and
// folders refused) with its size known before the first byte is read, so binary readers can
// check header counts against it before allocating.
// Every failure is one clhair::Error line naming the file and its format (`kind`).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "clhair/error.h"
#include "io/regular_file.h"

namespace clhair {

class InputFile {
 public:
  InputFile(const std::string& path, const std::string& kind) : file_(path, kind) {}

  std::uint64_t size() const { return file_.size(); }
  std::uint64_t offset() const { return offset_; }

  // Reads exactly n bytes; after the size checks only a file changed under us fails here.
  void read(unsigned char* dst, std::size_t n, const std::string& what) {
    file_.read(dst, n, what);
    offset_ += n;
  }

  void skip(std::uint64_t n, const std::string& what) { seek(offset_ + n, what); }

  // Moves to an absolute byte offset (formats whose header points at its arrays); callers
  // check the offset against size() first.
  void seek(std::uint64_t offset, const std::string& what) {
    file_.seek(offset, what);
    offset_ = offset;
  }

 private:
  RegularFile file_;
  std::uint64_t offset_ = 0;
};

// Little-endian decoding of the binary formats' fields, independent of the host's order.
inline std::uint32_t loadU32(const unsigned char* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
         std::uint32_t(p[3]) << 24;
}

inline std::uint16_t loadU16(const unsigned char* p) {
  return static_cast<std::uint16_t>(p[0] | p[1] << 8);
}

inline std::int32_t loadI32(const unsigned char* p) {
  const std::uint32_t u = loadU32(p);
  std::int32_t i;
  std::memcpy(&i, &u, sizeof(i));
  return i;
}

inline float loadF32(const unsigned char* p) {
  const std::uint32_t bits = loadU32(p);
  float f;
  std::memcpy(&f, &bits, sizeof(f));
  return f;
}

// Calls decode(index, bytes) for `count` consecutive elements of `elemBytes` each, reading at
// most about 1 MB at a time, so memory follows the data actually read.
template <typename Decode>
void readElements(InputFile& f, std::uint64_t count, std::size_t elemBytes, const std::string& what,
                  Decode decode) {
  constexpr std::size_t kChunkBytes = 1 << 20;
  std::vector<unsigned char> buf;
  const std::uint64_t perChunk = std::max<std::uint64_t>(1, kChunkBytes / elemBytes);
  for (std::uint64_t first = 0; first < count;) {
    const std::size_t n = static_cast<std::size_t>(std::min(perChunk, count - first));
    buf.resize(n * elemBytes);
    f.read(buf.data(), buf.size(), what);
    for (std::size_t k = 0; k < n; ++k) decode(first + k, buf.data() + k * elemBytes);
    first += n;
  }
}

// Little-endian encoding for the writers.
inline void appendU32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFFu));
}

inline void appendF32(std::string& out, float v) {
  std::uint32_t bits;
  std::memcpy(&bits, &v, sizeof(bits));
  appendU32(out, bits);
}

// The first bytes of a file as text for an error message, non-printable bytes as \xNN.
inline std::string showBytes(const unsigned char* p, std::size_t n) {
  std::string out;
  for (std::size_t i = 0; i < n; ++i) {
    if (p[i] >= 0x20 && p[i] < 0x7f && p[i] != '"' && p[i] != '\\') {
      out += static_cast<char>(p[i]);
    } else {
      char buf[8];
      std::snprintf(buf, sizeof(buf), "\\x%02x", p[i]);
      out += buf;
    }
  }
  return out;
}

// A float as error messages show it ("nan", "inf", "1e+30").
inline std::string showFloat(float v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", static_cast<double>(v));
  return buf;
}

}  // namespace clhair
