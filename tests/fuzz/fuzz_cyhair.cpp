// fuzz_cyhair.cpp — libFuzzer target for readCyHair (host/io/cyhair_read.cpp).
//
// Any input must either be refused with a clhair::Error or read into a CyHair whose arrays
// agree with each other and hold only finite floats; an accepted file must survive
// writeCyHair and read back identical. Anything else (another exception, a sanitizer
// report, a broken invariant) is a finding.
#include <cmath>
#include <cstdint>
#include <string>

#include "clhair/error.h"
#include "fuzz_util.h"
#include "io/cyhair.h"

namespace {

// Small enough that no accepted input costs much memory, large enough for any seed.
constexpr std::uint64_t kMaxBytes = 64ull << 20;

void checkConsistent(const clhair::CyHair& h) {
  std::uint64_t points = 0;
  for (std::uint32_t s : h.segments) points += std::uint64_t(s) + 1;
  CLHAIR_FUZZ_CHECK(!h.segments.empty());
  CLHAIR_FUZZ_CHECK(h.points.size() == 3 * points);
  CLHAIR_FUZZ_CHECK(h.thickness.empty() || h.thickness.size() == points);
  CLHAIR_FUZZ_CHECK(h.transparency.empty() || h.transparency.size() == points);
  CLHAIR_FUZZ_CHECK(h.colors.empty() || h.colors.size() == 3 * points);
  for (const auto* a : {&h.points, &h.thickness, &h.transparency, &h.colors})
    for (float v : *a) CLHAIR_FUZZ_CHECK(std::isfinite(v));
  CLHAIR_FUZZ_CHECK(h.info.size() <= 88);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = clhair::fuzz::writeInput(data, size, "input.hair");
  clhair::CyHair h;
  try {
    h = clhair::readCyHair(path, kMaxBytes);
  } catch (const clhair::Error&) {
    return 0;
  }
  checkConsistent(h);
  const std::string copy = clhair::fuzz::workDir() + "/copy.hair";
  clhair::writeCyHair(h, copy);  // segments are uint16 on disk, so the writer cannot refuse
  const clhair::CyHair r = clhair::readCyHair(copy, kMaxBytes);
  CLHAIR_FUZZ_CHECK(r.segments == h.segments);
  CLHAIR_FUZZ_CHECK(r.points == h.points);
  CLHAIR_FUZZ_CHECK(r.thickness == h.thickness);
  CLHAIR_FUZZ_CHECK(r.transparency == h.transparency);
  CLHAIR_FUZZ_CHECK(r.colors == h.colors);
  CLHAIR_FUZZ_CHECK(r.defaultThickness == h.defaultThickness);
  CLHAIR_FUZZ_CHECK(r.defaultTransparency == h.defaultTransparency);
  for (int c = 0; c < 3; ++c) CLHAIR_FUZZ_CHECK(r.defaultColor[c] == h.defaultColor[c]);
  // The writer keeps a terminating NUL, so it stores at most 87 of the 88 info bytes.
  CLHAIR_FUZZ_CHECK(r.info == h.info.substr(0, 87));
  return 0;
}
