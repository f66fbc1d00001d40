// ct2hair_read.cpp — reading CT2Hair `.bin` strand files (layout in ply_strands.h).
//
// Input: a path and a byte limit. Output: the strands as a CyHair (points only). Each
// strand's point count is checked against the bytes left before its points are read, and
// the running total against the limit; a strand with a non-finite coordinate is left out
// and counted, as CT2Hair's own loader drops such strands.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "clhair/error.h"
#include "io/binary_file.h"
#include "io/ply_strands.h"

namespace clhair {

PlyStrands readCt2HairBin(const std::string& path, std::uint64_t maxBytes) {
  InputFile f(path, "CT2Hair .bin");
  if (f.size() < 4)
    throw Error(path + ": is " + std::to_string(f.size()) +
                " bytes, too short for the CT2Hair strand count");
  unsigned char b4[4];
  f.read(b4, 4, "the strand count");
  const std::int32_t strands = loadI32(b4);
  if (strands <= 0)
    throw Error(path + ": the strand count is " + std::to_string(strands) +
                ", expected a positive number (is it a CT2Hair .bin file?)");
  if (static_cast<std::uint64_t>(strands) > (f.size() - 4) / 4)
    throw Error(path + ": truncated: " + std::to_string(strands) + " strands need at least " +
                std::to_string(4 + 4 * std::uint64_t(strands)) + " bytes, the file has " +
                std::to_string(f.size()));
  const std::uint64_t limit =
      std::min<std::uint64_t>(maxBytes, std::numeric_limits<std::size_t>::max());
  PlyStrands out;
  CyHair& h = out.hair;
  h.info = "CT2Hair";
  std::uint64_t memory = 0;
  for (std::int32_t s = 0; s < strands; ++s) {
    f.read(b4, 4, "the point count of strand " + std::to_string(s));
    const std::int32_t n = loadI32(b4);
    const std::uint64_t left = f.size() - f.offset();
    if (n < 0 || static_cast<std::uint64_t>(n) > left / 28)
      throw Error(path + ": " + (n < 0 ? std::string("") : std::string("truncated: ")) + "strand " +
                  std::to_string(s) + " has " + std::to_string(n) + " points" +
                  (n < 0 ? ", expected 0 or more"
                         : ", which need " + std::to_string(28 * std::uint64_t(n)) +
                               " bytes, but " + std::to_string(left) + " are left"));
    memory += 4 + 12 * std::uint64_t(n);
    if (memory > limit)
      throw Error(path + ": the strands need more than the " + std::to_string(limit) +
                  "-byte limit (the device's largest allocation)");
    std::vector<float> pts(static_cast<std::size_t>(3 * n));
    bool finite = true;
    readElements(f, static_cast<std::uint64_t>(n), 28, "strand " + std::to_string(s),
                 [&](std::uint64_t i, const unsigned char* b) {
                   for (int c = 0; c < 3; ++c) {
                     const float v = loadF32(b + 4 * c);
                     finite = finite && std::isfinite(v);
                     pts[static_cast<std::size_t>(3 * i + c)] = v;
                   }
                 });
    if (n < 2 || !finite) {
      ++out.skippedStrands;
      continue;
    }
    h.segments.push_back(static_cast<std::uint32_t>(n - 1));
    h.points.insert(h.points.end(), pts.begin(), pts.end());
  }
  if (h.segments.empty())
    throw Error(path + ": no strand has 2 or more finite points, nothing to draw");
  h.trailingBytes = f.size() - f.offset();
  return out;
}

}  // namespace clhair
