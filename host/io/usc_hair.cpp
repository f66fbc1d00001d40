// usc_hair.cpp — reading USC-HairSalon `.data` files (format in usc_hair.h).
//
// Input: a path and a byte limit. Output: the strands of 2 or more points as a CyHair and
// the number of shorter strands skipped. The strand count is checked against the file
// size before the first strand is read (every strand needs at least its 4-byte count), and
// every point count against the bytes left, so memory grows only with data actually in the
// file, and never past the limit. Points are read in bounded chunks and decoded from little
// endian byte by byte.
#include "io/usc_hair.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <vector>

#include "clhair/error.h"
#include "io/binary_file.h"

namespace clhair {

namespace {

constexpr std::uint64_t kPointBytes = 12;
constexpr std::size_t kChunkPoints = (1 << 20) / kPointBytes;

}  // namespace

UscHair readUscHair(const std::string& path, std::uint64_t maxBytes) {
  InputFile f(path, "USC-HairSalon");
  if (f.size() < 4)
    throw Error(path + ": is " + std::to_string(f.size()) +
                " bytes, too short for the USC-HairSalon strand count");
  unsigned char word[4];
  f.read(word, 4, "the strand count");
  const std::int32_t strandCount = loadI32(word);
  if (strandCount < 0)
    throw Error(path + ": strand count is " + std::to_string(strandCount) +
                ", negative (is it a USC-HairSalon .data file?)");
  if (strandCount == 0) throw Error(path + ": strand count is 0, the file holds no hair");
  const std::uint64_t strands = static_cast<std::uint64_t>(strandCount);
  // Each strand needs at least its 4-byte point count.
  if (4 + 4 * strands > f.size())
    throw Error(path + ": strand count is " + std::to_string(strands) + " but a file of " +
                std::to_string(f.size()) + " bytes holds at most " +
                std::to_string((f.size() - 4) / 4) + " strands (4 bytes each at least)");
  const std::uint64_t limit =
      std::min<std::uint64_t>(maxBytes, std::numeric_limits<std::size_t>::max());

  UscHair out;
  CyHair& h = out.hair;
  h.info = "USC-HairSalon";
  std::uint64_t memory = 0;
  std::vector<unsigned char> buf;
  for (std::uint64_t s = 0; s < strands; ++s) {
    const std::string strand = "strand " + std::to_string(s);
    f.read(word, 4, "the point count of " + strand);
    const std::int32_t pointCount = loadI32(word);
    if (pointCount < 0)
      throw Error(path + ": " + strand + " has a negative point count (" +
                  std::to_string(pointCount) + ") at byte " + std::to_string(f.offset() - 4));
    const std::uint64_t points = static_cast<std::uint64_t>(pointCount);
    // The points of this strand plus the counts of the strands after it must still fit.
    const std::uint64_t need = points * kPointBytes + 4 * (strands - s - 1);
    if (need > f.size() - f.offset())
      throw Error(path + ": truncated: " + strand + " of " + std::to_string(strands) + " says " +
                  std::to_string(points) + " points, which with the strands after it need " +
                  std::to_string(need) + " bytes after byte " + std::to_string(f.offset()) +
                  ", but the file has " + std::to_string(f.size()) + " bytes");
    if (points < 2) {
      f.skip(points * kPointBytes, "the single point of " + strand);
      ++out.skippedStrands;
      continue;
    }
    memory += 4 + points * kPointBytes;
    if (memory > limit)
      throw Error(path + ": the strands up to " + strand + " already need " +
                  std::to_string(memory) + " bytes of arrays, more than the " +
                  std::to_string(limit) + "-byte limit (the device's largest allocation)");
    h.segments.push_back(static_cast<std::uint32_t>(points - 1));
    const std::size_t base = h.points.size();
    h.points.resize(base + static_cast<std::size_t>(points) * 3);
    for (std::uint64_t first = 0; first < points;) {
      const std::size_t n =
          static_cast<std::size_t>(std::min<std::uint64_t>(kChunkPoints, points - first));
      buf.resize(n * kPointBytes);
      f.read(buf.data(), buf.size(), "the points of " + strand);
      for (std::size_t k = 0; k < 3 * n; ++k) {
        const float v = loadF32(buf.data() + 4 * k);
        if (!std::isfinite(v))
          throw Error(path + ": " + strand + " point " + std::to_string(first + k / 3) + " " +
                      std::string(1, "xyz"[k % 3]) + " is " + showFloat(v) +
                      ", expected a finite number");
        h.points[base + static_cast<std::size_t>(first) * 3 + k] = v;
      }
      first += n;
    }
  }
  if (h.segments.empty())
    throw Error(path + ": none of its " + std::to_string(strands) +
                " strands has 2 or more points, the file holds no renderable hair");
  h.trailingBytes = f.size() - f.offset();
  return out;
}

}  // namespace clhair
