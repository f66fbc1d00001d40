// fuzz_usc.cpp — libFuzzer target for readUscHair (host/io/usc_hair.cpp).
//
// Any input must either be refused with a clhair::Error or read into strands of at least
// 2 finite points each; anything else is a finding.
#include <cmath>
#include <cstdint>
#include <string>

#include "clhair/error.h"
#include "fuzz_util.h"
#include "io/usc_hair.h"

namespace {
constexpr std::uint64_t kMaxBytes = 64ull << 20;
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = clhair::fuzz::writeInput(data, size, "input.data");
  clhair::UscHair u;
  try {
    u = clhair::readUscHair(path, kMaxBytes);
  } catch (const clhair::Error&) {
    return 0;
  }
  const clhair::CyHair& h = u.hair;
  std::uint64_t points = 0;
  for (std::uint32_t s : h.segments) {
    CLHAIR_FUZZ_CHECK(s >= 1);
    points += std::uint64_t(s) + 1;
  }
  CLHAIR_FUZZ_CHECK(!h.segments.empty());
  CLHAIR_FUZZ_CHECK(h.points.size() == 3 * points);
  for (float v : h.points) CLHAIR_FUZZ_CHECK(std::isfinite(v));
  CLHAIR_FUZZ_CHECK(h.thickness.empty() && h.transparency.empty() && h.colors.empty());
  // Every strand, kept or skipped, had its 4-byte count in the file after the 4-byte total.
  CLHAIR_FUZZ_CHECK(4 + 4 * (h.segments.size() + u.skippedStrands) + 12 * points <= size);
  CLHAIR_FUZZ_CHECK(h.info == "USC-HairSalon");
  return 0;
}
