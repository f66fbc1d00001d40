// cage_io.cpp — the cage-animation file (docs/cage-animation-format.md): a hair mesh's layer
// vertices for every frame of a shot, float32, little endian.
//
// The reader checks the header against the file size and the byte limit before it
// allocates, then every coordinate (finite, within kMaxCoordinate like a hair mesh's
// vertices); any failure is one clhair::Error line naming the file.
#include <cmath>
#include <cstring>

#include "clhair/animation.h"
#include "clhair/error.h"
#include "clhair/hair_mesh.h"
#include "io/binary_file.h"
#include "io/json_util.h"

namespace clhair {

namespace {

constexpr char kMagic[8] = {'C', 'L', 'H', 'C', 'A', 'G', 'E', '\0'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kHeaderBytes = 24;  // magic, version, frames, vertices, reserved

}  // namespace

CageAnimation loadCageAnimation(const std::string& path, std::uint64_t maxBytes) {
  InputFile f(path, "cage-animation");
  if (f.size() < kHeaderBytes)
    throw Error(path + ": truncated cage-animation file: " + std::to_string(f.size()) +
                " bytes, shorter than the " + std::to_string(kHeaderBytes) + "-byte header");
  unsigned char h[kHeaderBytes];
  f.read(h, kHeaderBytes, "the header");
  if (std::memcmp(h, kMagic, sizeof(kMagic)) != 0)
    throw Error(path + ": not a cage-animation file (starts with \"" + showBytes(h, 8) +
                "\", expected \"CLHCAGE\\x00\")");
  const std::uint32_t version = loadU32(h + 8);
  if (version != kVersion)
    throw Error(path + ": cage-animation version " + std::to_string(version) +
                " is not supported (expected " + std::to_string(kVersion) + ")");
  CageAnimation c;
  c.frames = loadU32(h + 12);
  c.vertices = loadU32(h + 16);
  if (loadU32(h + 20) != 0)
    throw Error(path + ": reserved header field is " + std::to_string(loadU32(h + 20)) +
                ", expected 0");
  if (c.frames < 1 || c.frames > kMaxCageFrames)
    throw Error(path + ": header says " + std::to_string(c.frames) + " frames, expected 1.." +
                std::to_string(kMaxCageFrames));
  if (c.vertices < 1 || c.vertices > kMaxCageVertices)
    throw Error(path + ": header says " + std::to_string(c.vertices) + " vertices, expected 1.." +
                std::to_string(kMaxCageVertices));
  const std::uint64_t count = static_cast<std::uint64_t>(c.frames) * c.vertices;
  const std::uint64_t bytes = count * 12;
  if (f.size() != kHeaderBytes + bytes)
    throw Error(path + ": " + (f.size() < kHeaderBytes + bytes ? "truncated" : "wrong size") +
                ": header says " + std::to_string(c.frames) + " frames of " +
                std::to_string(c.vertices) + " vertices (" + std::to_string(kHeaderBytes + bytes) +
                " bytes), the file has " + std::to_string(f.size()) + " bytes");
  if (bytes > maxBytes)
    throw Error(path + ": " + std::to_string(c.frames) + " frames of " +
                std::to_string(c.vertices) + " vertices need " + std::to_string(bytes >> 20) +
                " MiB, over the limit of " + std::to_string(maxBytes >> 20) + " MiB");
  c.positions.resize(count);
  readElements(f, count, 12, "cage positions", [&](std::uint64_t i, const unsigned char* p) {
    glm::vec3 v(loadF32(p), loadF32(p + 4), loadF32(p + 8));
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      throw Error(path + ": frame " + std::to_string(i / c.vertices) + ", vertex " +
                  std::to_string(i % c.vertices) + " has a non-finite coordinate (" +
                  showFloat(v.x) + ", " + showFloat(v.y) + ", " + showFloat(v.z) + ")");
    // the bound of a hair mesh's layer vertices, which these positions replace
    if (std::fabs(v.x) > kMaxCoordinate || std::fabs(v.y) > kMaxCoordinate ||
        std::fabs(v.z) > kMaxCoordinate)
      throw Error(path + ": frame " + std::to_string(i / c.vertices) + ", vertex " +
                  std::to_string(i % c.vertices) + " is at (" + showFloat(v.x) + ", " +
                  showFloat(v.y) + ", " + showFloat(v.z) +
                  "), beyond the +-1e6 coordinates a hair mesh allows");
    c.positions[i] = v;
  });
  return c;
}

void saveCageAnimation(const CageAnimation& c, const std::string& path) {
  if (c.frames < 1 || c.vertices < 1 ||
      c.positions.size() != static_cast<std::size_t>(c.frames) * c.vertices)
    throw Error(path + ": refusing to write an empty or inconsistent cage animation");
  std::string out(kMagic, sizeof(kMagic));
  appendU32(out, kVersion);
  appendU32(out, c.frames);
  appendU32(out, c.vertices);
  appendU32(out, 0);
  out.reserve(out.size() + c.positions.size() * 12);
  for (const glm::vec3& p : c.positions) {
    appendF32(out, p.x);
    appendF32(out, p.y);
    appendF32(out, p.z);
  }
  writeTextAtomically(path, out);
}

}  // namespace clhair
