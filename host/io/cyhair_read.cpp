// cyhair_read.cpp — reading cyHair `.hair` files (format in cyhair.h).
//
// Input: a path and a byte limit. Output: a CyHair whose arrays agree with each other
// (segments per strand, 3 floats per point, optional per-point arrays full length).
// Nothing is allocated from a header count until the whole layout it implies has been
// checked against the file size and the limit, so a hostile header costs nothing. Arrays
// are read in bounded chunks and decoded from little endian byte by byte, so the reader
// does not depend on the host's byte order.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "clhair/error.h"
#include "io/binary_file.h"
#include "io/cyhair.h"

namespace clhair {

namespace {

constexpr std::uint64_t kHeaderBytes = 128;
constexpr std::uint32_t kSegmentsBit = 1u, kPointsBit = 2u, kThicknessBit = 4u,
                        kTransparencyBit = 8u, kColorsBit = 16u;
constexpr std::uint32_t kKnownBits =
    kSegmentsBit | kPointsBit | kThicknessBit | kTransparencyBit | kColorsBit;

// "1 strand", "2 strands".
std::string count(std::uint64_t n, const char* noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

std::string hex(std::uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof(buf), "0x%x", v);
  return buf;
}

// The strand holding point p (used only to word an error message).
std::uint64_t strandOfPoint(const std::vector<std::uint32_t>& segments, std::uint64_t p) {
  std::uint64_t end = 0;
  for (std::size_t s = 0; s < segments.size(); ++s) {
    end += std::uint64_t(segments[s]) + 1;
    if (p < end) return s;
  }
  return segments.size();
}

constexpr const char* kXyz[] = {"x", "y", "z"};
constexpr const char* kRgb[] = {"r", "g", "b"};

// Reads one float per point (names == nullptr) or three named ones into out, rejecting
// non-finite values.
void readFloats(InputFile& f, const std::string& path, const CyHair& h, std::uint64_t points,
                const char* const* names, const char* what, std::vector<float>& out) {
  const int perPoint = names ? 3 : 1;
  out.resize(static_cast<std::size_t>(points) * perPoint);
  readElements(f, points * perPoint, 4, what, [&](std::uint64_t i, const unsigned char* b) {
    const float v = loadF32(b);
    if (!std::isfinite(v)) {
      const std::uint64_t point = i / perPoint;
      std::string which = "point " + std::to_string(point);
      if (names) which += std::string(" ") + names[i % 3];
      throw Error(path + ": " + what + ": " + which + " (strand " +
                  std::to_string(strandOfPoint(h.segments, point)) + ") is " + showFloat(v) +
                  ", expected a finite number");
    }
    out[static_cast<std::size_t>(i)] = v;
  });
}

}  // namespace

CyHair readCyHair(const std::string& path, std::uint64_t maxBytes) {
  InputFile f(path, "cyHair");
  if (f.size() < kHeaderBytes)
    throw Error(path + ": is " + std::to_string(f.size()) + " bytes, shorter than the " +
                std::to_string(kHeaderBytes) + "-byte cyHair header");
  unsigned char header[kHeaderBytes];
  f.read(header, sizeof(header), "header");
  if (std::memcmp(header, "HAIR", 4) != 0)
    throw Error(path + ": starts with \"" + showBytes(header, 4) +
                "\", not the cyHair signature \"HAIR\" (is it a cyHair .hair file?)");

  const std::uint64_t strands = loadU32(header + 4);
  const std::uint64_t points = loadU32(header + 8);
  const std::uint32_t flags = loadU32(header + 12);
  const std::uint64_t defaultSegments = loadU32(header + 16);
  CyHair h;
  h.defaultThickness = loadF32(header + 20);
  h.defaultTransparency = loadF32(header + 24);
  for (int c = 0; c < 3; ++c) h.defaultColor[c] = loadF32(header + 28 + 4 * c);
  const char* info = reinterpret_cast<const char*>(header + 40);
  const void* nul = std::memchr(info, 0, 88);
  h.info.assign(info, nul ? static_cast<const char*>(nul) - info : 88);

  if (strands == 0) throw Error(path + ": header says 0 strands, the file holds no hair");
  if (flags & ~kKnownBits)
    throw Error(path + ": flags " + hex(flags) + " set unknown bits " + hex(flags & ~kKnownBits) +
                " (known: 0x1 segments, 0x2 points, 0x4 thickness, 0x8 transparency, " +
                "0x10 colour)");
  if (!(flags & kPointsBit))
    throw Error(path + ": has no points array (flags " + hex(flags) +
                "), so there is no geometry to read");
  const struct {
    const char* name;
    float value;
  } defaults[] = {{"default thickness", h.defaultThickness},
                  {"default transparency", h.defaultTransparency},
                  {"default colour r", h.defaultColor[0]},
                  {"default colour g", h.defaultColor[1]},
                  {"default colour b", h.defaultColor[2]}};
  for (const auto& d : defaults)
    if (!std::isfinite(d.value))
      throw Error(path + ": header " + d.name + " is " + showFloat(d.value) +
                  ", expected a finite number");
  const bool hasSegments = flags & kSegmentsBit;
  // strands < 2^32 and defaultSegments + 1 <= 2^32, so the product fits in 64 bits.
  if (!hasSegments && strands * (defaultSegments + 1) != points)
    throw Error(path + ": header says " + std::to_string(points) + " points but " +
                std::to_string(strands) + " strands of " + std::to_string(defaultSegments) +
                " default segments make " + std::to_string(strands * (defaultSegments + 1)) +
                " (there is no segments array)");

  // The layout the header implies; with counts below 2^32 no sum here can overflow.
  const struct {
    const char* name;
    std::uint64_t bytes;
  } arrays[] = {{"segments array", hasSegments ? 2 * strands : 0},
                {"points array", 12 * points},
                {"thickness array", flags & kThicknessBit ? 4 * points : 0},
                {"transparency array", flags & kTransparencyBit ? 4 * points : 0},
                {"colour array", flags & kColorsBit ? 12 * points : 0}};
  std::uint64_t expected = kHeaderBytes;
  for (const auto& a : arrays) {
    if (f.size() < expected + a.bytes)
      throw Error(path + ": truncated: header says " + count(strands, "strand") + " and " +
                  count(points, "point") + " (flags " + hex(flags) + "), the " + a.name +
                  " ends at byte " + std::to_string(expected + a.bytes) + " but the file has " +
                  std::to_string(f.size()) + " bytes");
    expected += a.bytes;
  }
  const std::uint64_t memory =
      4 * strands + 12 * points + (flags & kThicknessBit ? 4 * points : 0) +
      (flags & kTransparencyBit ? 4 * points : 0) + (flags & kColorsBit ? 12 * points : 0);
  const std::uint64_t limit =
      std::min<std::uint64_t>(maxBytes, std::numeric_limits<std::size_t>::max());
  if (memory > limit)
    throw Error(path + ": " + count(strands, "strand") + " and " + count(points, "point") +
                " need " + std::to_string(memory) + " bytes of arrays, more than the " +
                std::to_string(limit) + "-byte limit (the device's largest allocation)");

  h.segments.assign(static_cast<std::size_t>(strands), static_cast<std::uint32_t>(defaultSegments));
  if (hasSegments) {
    readElements(f, strands, 2, "segments array", [&](std::uint64_t i, const unsigned char* b) {
      h.segments[static_cast<std::size_t>(i)] = loadU16(b);
    });
    std::uint64_t sum = 0;
    for (std::uint32_t s : h.segments) sum += std::uint64_t(s) + 1;
    if (sum != points)
      throw Error(path + ": header says " + std::to_string(points) +
                  " points but the segments array adds up to " + std::to_string(sum));
  }
  readFloats(f, path, h, points, kXyz, "points array", h.points);
  if (flags & kThicknessBit)
    readFloats(f, path, h, points, nullptr, "thickness array", h.thickness);
  if (flags & kTransparencyBit)
    readFloats(f, path, h, points, nullptr, "transparency array", h.transparency);
  if (flags & kColorsBit) readFloats(f, path, h, points, kRgb, "colour array", h.colors);
  h.trailingBytes = f.size() - expected;
  return h;
}

}  // namespace clhair
