// binary_file.h — a regular file opened for reading with its size known before the first
// byte is read, so binary readers can check header counts against it before allocating.
// Every failure is one clhair::Error line naming the file and its format (`kind`).
#pragma once

#include <cerrno>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "clhair/error.h"

namespace clhair {

class InputFile {
 public:
  InputFile(const std::string& path, const std::string& kind) : path_(path) {
    std::error_code ec;
    auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status))
      throw Error(path + ": cannot open " + kind + " file (" + (ec ? ec.message() : std::string("no such file")) + ")");
    if (!std::filesystem::is_regular_file(status))
      throw Error(path + ": is not a regular file, cannot read it as a " + kind + " file");
    size_ = std::filesystem::file_size(path, ec);
    if (ec) throw Error(path + ": cannot read the size of the " + kind + " file (" + ec.message() + ")");
    in_.open(path, std::ios::binary);
    if (!in_) throw Error(path + ": cannot open " + kind + " file (" + std::strerror(errno) + ")");
  }

  std::uint64_t size() const { return size_; }
  std::uint64_t offset() const { return offset_; }

  // Reads exactly n bytes; after the size checks only a file changed under us fails here.
  void read(unsigned char* dst, std::size_t n, const std::string& what) {
    in_.read(reinterpret_cast<char*>(dst), static_cast<std::streamsize>(n));
    if (static_cast<std::size_t>(in_.gcount()) != n)
      throw Error(path_ + ": file ended early while reading " + what + " (was it changed while being read?)");
    offset_ += n;
  }

  void skip(std::uint64_t n, const std::string& what) {
    in_.seekg(static_cast<std::streamoff>(n), std::ios::cur);
    if (!in_) throw Error(path_ + ": cannot skip over " + what);
    offset_ += n;
  }

 private:
  std::string path_;
  std::ifstream in_;
  std::uint64_t size_ = 0;
  std::uint64_t offset_ = 0;
};

// Little-endian decoding of the binary formats' fields, independent of the host's order.
inline std::uint32_t loadU32(const unsigned char* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
}

inline std::uint16_t loadU16(const unsigned char* p) { return static_cast<std::uint16_t>(p[0] | p[1] << 8); }

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

// A float as error messages show it ("nan", "inf", "1e+30").
inline std::string showFloat(float v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", static_cast<double>(v));
  return buf;
}

}  // namespace clhair
