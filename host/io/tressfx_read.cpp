// tressfx_read.cpp — reading TressFX `.tfx` files (layouts in tressfx.h).
//
// Input: a path and a byte limit. Output: the strands as a CyHair (each with the file's
// vertices per strand) and the strand uv when the file has them. The version field picks
// the layout; every array the header names is checked against the file size, and the
// arrays kept against the limit, before anything is allocated, so a hostile header costs
// nothing. Arrays are read in bounded chunks and decoded from little endian byte by byte.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "clhair/error.h"
#include "io/binary_file.h"
#include "io/tressfx.h"

namespace clhair {

namespace {

constexpr std::uint64_t kHeader3Bytes = 296, kHeader4Bytes = 160;

// One array named by the header: where it starts and how many elements of what size.
struct ArrayRef {
  const char* name;
  std::uint64_t offset;  // 0: absent
  std::uint64_t count;
  std::uint64_t elemBytes;
  bool required;
};

// The first four bytes of a TressFX 1.x/2.x text file are printable text.
bool looksLikeText(const unsigned char* p) {
  for (int i = 0; i < 4; ++i)
    if (!(p[i] >= 0x20 && p[i] < 0x7f) && p[i] != '\t' && p[i] != '\n' && p[i] != '\r')
      return false;
  return true;
}

std::string layoutName(int major, float version) {
  return "TressFX " + std::to_string(major) + ".x, version " + showFloat(version);
}

}  // namespace

TressFxHair readTressFx(const std::string& path, std::uint64_t maxBytes) {
  InputFile f(path, "TressFX");
  if (f.size() < 4)
    throw Error(path + ": is " + std::to_string(f.size()) +
                " bytes, too short for the TressFX version field");
  unsigned char first[4];
  f.read(first, 4, "the version field");
  const float version = loadF32(first);
  int major = 0;
  if (version >= 3.0f && version < 4.0f)
    major = 3;
  else if (version >= 4.0f && version < 5.0f)
    major = 4;
  else if (looksLikeText(first))
    throw Error(
        path + ": starts with the text \"" + showBytes(first, 4) +
        "\": the TressFX 1.x/2.x text layout is not supported, only the binary 3.x and 4.x " +
        "layouts (re-export the groom as TressFX 4)");
  else
    throw Error(path + ": version field is " + showFloat(version) + " (bytes \"" +
                showBytes(first, 4) +
                "\"), expected 3.x or 4.x (is it a binary TressFX .tfx file?)");

  const std::uint64_t headerBytes = major == 3 ? kHeader3Bytes : kHeader4Bytes;
  if (f.size() < headerBytes)
    throw Error(path + ": is " + std::to_string(f.size()) + " bytes, shorter than the " +
                std::to_string(headerBytes) + "-byte header of " + layoutName(major, version));
  unsigned char header[kHeader3Bytes];
  f.seek(0, "the header");
  f.read(header, static_cast<std::size_t>(headerBytes), "the header");
  const std::uint64_t strands = loadU32(header + 4);
  const std::uint64_t perStrand = loadU32(header + 8);
  const std::string layout = layoutName(major, version);
  if (strands == 0)
    throw Error(path + ": header says 0 strands, the file holds no hair (" + layout + ")");
  if (perStrand < 2)
    throw Error(path + ": header says " + std::to_string(perStrand) +
                " vertices per strand, need at least 2 (TressFX uses 4 to 64; " + layout + ")");
  const std::uint64_t points = strands * perStrand;  // both below 2^32: no overflow

  const std::uint64_t positionBytes = major == 3 ? 12 : 16;
  ArrayRef positions{"vertex positions", loadU32(header + (major == 3 ? 144 : 12)), points,
                     positionBytes, true};
  ArrayRef strandUv{"strand uv", loadU32(header + (major == 3 ? 152 : 16)), strands, 8, false};
  // Arrays named by the header that are checked to fit but not read.
  const ArrayRef unread3[] = {{"strand thickness", loadU32(header + 148), strands, 4, false},
                              {"vertex colours", loadU32(header + 156), points, 16, false},
                              {"guide strand indices", loadU32(header + 160), strands, 4, false},
                              {"vertex uv", loadU32(header + 164), points, 8, false}};
  const ArrayRef unread4[] = {{"vertex uv", loadU32(header + 20), points, 8, false},
                              {"strand thickness", loadU32(header + 24), strands, 4, false},
                              {"vertex colours", loadU32(header + 28), points, 16, false}};

  // Every named array must start past the header and end inside the file. The end is
  // compared by division so that no product of header counts can overflow.
  std::uint64_t end = headerBytes;
  std::vector<const ArrayRef*> all = {&positions, &strandUv};
  if (major == 3)
    for (const ArrayRef& a : unread3) all.push_back(&a);
  else
    for (const ArrayRef& a : unread4) all.push_back(&a);
  for (const ArrayRef* a : all) {
    if (a->offset == 0) {
      if (a->required)
        throw Error(path + ": header gives no offset for the " + a->name +
                    " (0), so there is no geometry to read (" + layout + ")");
      continue;
    }
    const std::string what = std::string("the ") + a->name + " (" + std::to_string(a->count) +
                             " x " + std::to_string(a->elemBytes) + " bytes from byte " +
                             std::to_string(a->offset) + ")";
    if (a->offset < headerBytes)
      throw Error(path + ": " + what + " start inside the " + std::to_string(headerBytes) +
                  "-byte header (" + layout + ")");
    if (a->offset > f.size() || a->count > (f.size() - a->offset) / a->elemBytes)
      throw Error(path + ": truncated: header says " + std::to_string(strands) + " strands of " +
                  std::to_string(perStrand) + " vertices, " + what + " end past the file's " +
                  std::to_string(f.size()) + " bytes (" + layout + ")");
    end = std::max(end, a->offset + a->count * a->elemBytes);
  }

  const bool hasUv = strandUv.offset != 0;
  const std::uint64_t memory = 4 * strands + 12 * points + (hasUv ? 8 * strands : 0);
  const std::uint64_t limit =
      std::min<std::uint64_t>(maxBytes, std::numeric_limits<std::size_t>::max());
  if (memory > limit)
    throw Error(path + ": " + std::to_string(strands) + " strands of " + std::to_string(perStrand) +
                " vertices need " + std::to_string(memory) + " bytes of arrays, more than the " +
                std::to_string(limit) + "-byte limit (the device's largest allocation)");

  TressFxHair t;
  t.version = version;
  CyHair& h = t.hair;
  h.info = layout;
  h.segments.assign(static_cast<std::size_t>(strands), static_cast<std::uint32_t>(perStrand - 1));
  h.points.resize(static_cast<std::size_t>(points) * 3);
  const int components = major == 3 ? 3 : 4;
  auto nonFinite = [&](const char* array, std::uint64_t strand, const std::string& element,
                       float v) {
    return Error(path + ": " + array + ": strand " + std::to_string(strand) + " " + element +
                 " is " + showFloat(v) + ", expected a finite number");
  };
  f.seek(positions.offset, "the vertex positions");
  readElements(f, points, static_cast<std::size_t>(positionBytes), "the vertex positions",
               [&](std::uint64_t i, const unsigned char* b) {
                 for (int c = 0; c < components; ++c) {
                   const float v = loadF32(b + 4 * c);
                   if (!std::isfinite(v))
                     throw nonFinite(
                         "vertex positions", i / perStrand,
                         "vertex " + std::to_string(i % perStrand) + " " +
                             (c < 3 ? std::string(1, "xyz"[c]) : std::string("w (inverse mass)")),
                         v);
                   if (c < 3) h.points[static_cast<std::size_t>(3 * i + c)] = v;
                 }
               });
  if (hasUv) {
    t.strandUv.resize(static_cast<std::size_t>(strands) * 2);
    f.seek(strandUv.offset, "the strand uv");
    readElements(f, strands, 8, "the strand uv", [&](std::uint64_t s, const unsigned char* b) {
      for (int c = 0; c < 2; ++c) {
        const float v = loadF32(b + 4 * c);
        if (!std::isfinite(v)) throw nonFinite("strand uv", s, c == 0 ? "u" : "v", v);
        t.strandUv[static_cast<std::size_t>(2 * s + c)] = v;
      }
    });
  }
  h.trailingBytes = f.size() - end;
  return t;
}

}  // namespace clhair
