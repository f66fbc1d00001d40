// visibility_io.cpp — reads and writes baked visibility files (include/clhair/visibility.h).
#include <cmath>
#include <cstring>
#include <string>

#include "clhair/error.h"
#include "clhair/visibility.h"
#include "clhair/visibility_sh.h"
#include "io/binary_file.h"
#include "io/json_util.h"

namespace clhair {

namespace {

constexpr char kMagic[9] = "CLHVIS01";
constexpr std::uint32_t kVersion = 1;
constexpr std::uint64_t kCoefficients = std::uint64_t(CLH_VIS_CELLS) * CLH_VIS_COEFFS;

}  // namespace

VisibilityBake readVisibility(const std::string& path) {
  InputFile f(path, "baked visibility");
  const std::string kind = path + ": baked visibility file";
  const std::uint64_t expected = kVisibilityHeaderBytes + 4 * kCoefficients;
  if (f.size() < kVisibilityHeaderBytes)
    throw Error(kind + " is truncated: " + std::to_string(f.size()) +
                " bytes, the header alone is " + std::to_string(kVisibilityHeaderBytes));
  unsigned char h[kVisibilityHeaderBytes];
  f.read(h, sizeof(h), "the header");
  if (std::memcmp(h, kMagic, 8) != 0)
    throw Error(kind + " does not start with \"CLHVIS01\" (not written by clhair bake-visibility)");
  const std::uint32_t version = loadU32(h + 8), axis = loadU32(h + 12), coeffs = loadU32(h + 16);
  if (version != kVersion)
    throw Error(kind + " has version " + std::to_string(version) + ", this clhair reads version " +
                std::to_string(kVersion) + " (bake it again)");
  if (axis != CLH_VIS_AXIS || coeffs != CLH_VIS_COEFFS)
    throw Error(kind + " has " + std::to_string(axis) + " cells per axis and " +
                std::to_string(coeffs) + " coefficients per cell, need " +
                std::to_string(CLH_VIS_AXIS) + " and " + std::to_string(CLH_VIS_COEFFS));
  VisibilityBake b;
  b.strands = loadU32(h + 20);
  b.raysPerPoint = loadU32(h + 24);
  b.pointsPerCell = loadU32(h + 28);
  b.maxScatterEvents = loadF32(h + 32);
  if (b.strands == 0) throw Error(kind + " was baked for 0 strands");
  if (b.raysPerPoint == 0 || b.pointsPerCell == 0)
    throw Error(kind + " has " + std::to_string(b.raysPerPoint) + " rays per point and " +
                std::to_string(b.pointsPerCell) + " points per cell, need at least 1 of each");
  if (!(b.maxScatterEvents >= 0.0f && b.maxScatterEvents <= 100.0f))
    throw Error(kind + " has a miss bias of " + std::to_string(b.maxScatterEvents) +
                " events, need 0..100");
  if (f.size() != expected)
    throw Error(kind + (f.size() < expected ? " is truncated" : " has trailing bytes") + ": " +
                std::to_string(f.size()) + " bytes, 64^3 cells of 4 coefficients need " +
                std::to_string(expected));
  b.sh.resize(kCoefficients);
  readElements(f, kCoefficients, 4, "the SH coefficients",
               [&](std::uint64_t i, const unsigned char* p) {
                 const float c = loadF32(p);
                 if (!std::isfinite(c) || std::fabs(c) > kMaxVisibilityCoefficient)
                   throw Error(kind + ": coefficient " + std::to_string(i % CLH_VIS_COEFFS) +
                               " of cell " + std::to_string(i / CLH_VIS_COEFFS) + " is " +
                               std::to_string(c) + ", need a finite value within +-" +
                               std::to_string(static_cast<int>(kMaxVisibilityCoefficient)));
                 b.sh[i] = c;
               });
  return b;
}

void writeVisibility(const VisibilityBake& b, const std::string& path) {
  if (b.sh.size() != kCoefficients)
    throw Error(path + ": a visibility bake of " + std::to_string(b.sh.size()) +
                " coefficients, need " + std::to_string(kCoefficients));
  std::string out;
  out.reserve(kVisibilityHeaderBytes + 4 * kCoefficients);
  out.append(kMagic, 8);
  appendU32(out, kVersion);
  appendU32(out, CLH_VIS_AXIS);
  appendU32(out, CLH_VIS_COEFFS);
  appendU32(out, b.strands);
  appendU32(out, b.raysPerPoint);
  appendU32(out, b.pointsPerCell);
  appendF32(out, b.maxScatterEvents);
  appendU32(out, 0);
  for (float c : b.sh) appendF32(out, c);
  writeTextAtomically(path, out);
}

}  // namespace clhair
