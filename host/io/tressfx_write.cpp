// tressfx_write.cpp — writing TressFX 4.0 `.tfx` files (layout in tressfx.h) and resampling
// strands to the equal point count the format needs.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "clhair/error.h"
#include "io/binary_file.h"
#include "io/json_util.h"
#include "io/tressfx.h"

namespace clhair {

namespace {

constexpr std::uint32_t kHeaderBytes = 160;

}  // namespace

void writeTressFx(const TressFxHair& tfx, const std::string& path) {
  const CyHair& h = tfx.hair;
  const std::uint64_t strands = h.segments.size();
  if (strands == 0) throw Error(path + ": no strands to write");
  const std::uint64_t perStrand = std::uint64_t(h.segments[0]) + 1;
  for (std::size_t s = 0; s < h.segments.size(); ++s)
    if (h.segments[s] != h.segments[0])
      throw Error(path + ": strand " + std::to_string(s) + " has " +
                  std::to_string(h.segments[s] + 1ull) + " points but strand 0 has " +
                  std::to_string(perStrand) +
                  "; TressFX needs the same count in every strand (resample first)");
  if (perStrand < 2) throw Error(path + ": strands of 1 point cannot be written as TressFX");
  const std::uint64_t points = strands * perStrand;
  if (h.points.size() != 3 * points)
    throw Error(path + ": point array does not match the segment counts");
  if (!tfx.strandUv.empty() && tfx.strandUv.size() != 2 * strands)
    throw Error(path + ": " + std::to_string(tfx.strandUv.size()) + " strand uv values for " +
                std::to_string(strands) + " strands");
  const std::uint64_t uvOffset = kHeaderBytes + 16 * points;
  const std::uint64_t total = uvOffset + (tfx.strandUv.empty() ? 0 : 8 * strands);
  if (total > 0xFFFFFFFFull)
    throw Error(path + ": " + std::to_string(strands) + " strands of " + std::to_string(perStrand) +
                " points make a " + std::to_string(total) +
                "-byte file; TressFX offsets are 32-bit (under 4 GiB)");

  std::string out;
  out.reserve(static_cast<std::size_t>(total));
  appendF32(out, 4.0f);
  appendU32(out, static_cast<std::uint32_t>(strands));
  appendU32(out, static_cast<std::uint32_t>(perStrand));
  appendU32(out, kHeaderBytes);  // vertex positions
  appendU32(out, tfx.strandUv.empty() ? 0u : static_cast<std::uint32_t>(uvOffset));  // strand uv
  for (int i = 0; i < 3 + 32; ++i) appendU32(out, 0);  // vertex uv, thickness, colour; reserved
  for (std::uint64_t p = 0; p < points; ++p) {
    for (int c = 0; c < 3; ++c) appendF32(out, h.points[static_cast<std::size_t>(3 * p + c)]);
    appendF32(out, p % perStrand < 2 ? 0.0f : 1.0f);  // inverse mass: TressFX pins the first two
  }
  for (float v : tfx.strandUv) appendF32(out, v);
  writeTextAtomically(path, out);
}

std::uint32_t tressFxVertexCount(const CyHair& hair) {
  std::uint64_t longest = 0;
  for (std::uint32_t s : hair.segments)
    longest = std::max<std::uint64_t>(longest, std::uint64_t(s) + 1);
  std::uint32_t n = 4;
  while (n < 64 && 2ull * n <= longest) n *= 2;
  return n;
}

CyHair resampleStrands(const CyHair& hair, std::uint32_t points) {
  if (points < 2)
    throw Error("resampling strands to " + std::to_string(points) + " points, need at least 2");
  CyHair out;
  out.info = hair.info;
  out.defaultThickness = hair.defaultThickness;
  out.defaultTransparency = hair.defaultTransparency;
  std::copy(std::begin(hair.defaultColor), std::end(hair.defaultColor),
            std::begin(out.defaultColor));
  out.segments.assign(hair.segments.size(), points - 1);
  out.points.reserve(hair.segments.size() * points * 3);
  std::vector<double> along;  // arc length at each input point
  std::size_t at = 0;         // first input point of the strand
  for (std::uint32_t seg : hair.segments) {
    const std::size_t n = std::size_t(seg) + 1;
    const float* p = hair.points.data() + 3 * at;
    along.assign(n, 0.0);
    for (std::size_t k = 1; k < n; ++k) {
      const double dx = p[3 * k] - p[3 * k - 3], dy = p[3 * k + 1] - p[3 * k - 2],
                   dz = p[3 * k + 2] - p[3 * k - 1];
      along[k] = along[k - 1] + std::sqrt(dx * dx + dy * dy + dz * dz);
    }
    const double length = along[n - 1];
    std::size_t k = 0;  // segment [k, k + 1] holding the current target
    for (std::uint32_t j = 0; j < points; ++j) {
      if (j == points - 1 && length > 0.0) {  // the tip exactly
        out.points.insert(out.points.end(), {p[3 * n - 3], p[3 * n - 2], p[3 * n - 1]});
        continue;
      }
      const double target = length * j / (points - 1);
      while (k + 2 < n && along[k + 1] < target) ++k;
      if (n == 1 || length == 0.0) {
        out.points.insert(out.points.end(), {p[0], p[1], p[2]});
        continue;
      }
      const double span = along[k + 1] - along[k];
      const double t = span > 0.0 ? std::clamp((target - along[k]) / span, 0.0, 1.0) : 0.0;
      for (int c = 0; c < 3; ++c)
        out.points.push_back(
            static_cast<float>(p[3 * k + c] + t * (double(p[3 * k + 3 + c]) - p[3 * k + c])));
    }
    at += n;
  }
  return out;
}

}  // namespace clhair
