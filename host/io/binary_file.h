// binary_file.h — a regular file opened for reading with its size known before the first
// byte is read, so binary readers can check header counts against it before allocating.
// Every failure is one clhair::Error line naming the file and its format (`kind`).
#pragma once

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "clhair/error.h"

namespace clhair {

class InputFile {
 public:
  InputFile(const std::string& path, const std::string& kind) : path_(path) {
    std::error_code ec;
    auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status))
      throw Error(path + ": cannot open " + kind + " file (" +
                  (ec ? ec.message() : std::string("no such file")) + ")");
    if (!std::filesystem::is_regular_file(status))
      throw Error(path + ": is not a regular file, cannot read it as a " + kind + " file");
    size_ = std::filesystem::file_size(path, ec);
    if (ec)
      throw Error(path + ": cannot read the size of the " + kind + " file (" + ec.message() + ")");
    in_.open(path, std::ios::binary);
    if (!in_) throw Error(path + ": cannot open " + kind + " file (" + std::strerror(errno) + ")");
  }

  std::uint64_t size() const { return size_; }
  std::uint64_t offset() const { return offset_; }

  // Reads exactly n bytes; after the size checks only a file changed under us fails here.
  void read(unsigned char* dst, std::size_t n, const std::string& what) {
    in_.read(reinterpret_cast<char*>(dst), static_cast<std::streamsize>(n));
    if (static_cast<std::size_t>(in_.gcount()) != n)
      throw Error(path_ + ": file ended early while reading " + what +
                  " (was it changed while being read?)");
    offset_ += n;
  }

  void skip(std::uint64_t n, const std::string& what) {
    in_.seekg(static_cast<std::streamoff>(n), std::ios::cur);
    if (!in_) throw Error(path_ + ": cannot skip over " + what);
    offset_ += n;
  }

  // Moves to an absolute byte offset (formats whose header points at its arrays); callers
  // check the offset against size() first.
  void seek(std::uint64_t offset, const std::string& what) {
    in_.seekg(static_cast<std::streamoff>(offset), std::ios::beg);
    if (!in_)
      throw Error(path_ + ": cannot seek to " + what + " at byte " + std::to_string(offset));
    offset_ = offset;
  }

 private:
  std::string path_;
  std::ifstream in_;
  std::uint64_t size_ = 0;
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
