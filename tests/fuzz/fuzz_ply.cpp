// fuzz_ply.cpp — libFuzzer target for readPlyStrands and readCt2HairBin
// (host/io/ply_read.cpp).
//
// The input is read both as a PLY file and as a CT2Hair .bin file. Each must either be
// refused with a clhair::Error or read into strands of at least 2 finite points each, with
// colours (when present) one linear rgb in [0, 1] per point; anything else is a finding.
#include <cmath>
#include <cstdint>
#include <string>

#include "clhair/error.h"
#include "fuzz_util.h"
#include "io/ply_strands.h"

namespace {

constexpr std::uint64_t kMaxBytes = 64ull << 20;

void check(const clhair::PlyStrands& p, std::size_t size) {
  const clhair::CyHair& h = p.hair;
  std::uint64_t points = 0;
  for (std::uint32_t s : h.segments) {
    CLHAIR_FUZZ_CHECK(s >= 1);
    points += std::uint64_t(s) + 1;
  }
  CLHAIR_FUZZ_CHECK(!h.segments.empty());
  CLHAIR_FUZZ_CHECK(h.points.size() == 3 * points);
  for (float v : h.points) CLHAIR_FUZZ_CHECK(std::isfinite(v));
  CLHAIR_FUZZ_CHECK(h.colors.empty() || h.colors.size() == 3 * points);
  for (float c : h.colors) CLHAIR_FUZZ_CHECK(c >= 0.0f && c <= 1.0f);
  CLHAIR_FUZZ_CHECK(h.thickness.empty() && h.transparency.empty());
  CLHAIR_FUZZ_CHECK(h.trailingBytes <= size);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string ply = clhair::fuzz::writeInput(data, size, "input.ply");
  try {
    check(clhair::readPlyStrands(ply, kMaxBytes), size);
  } catch (const clhair::Error&) {
  }
  const std::string bin = clhair::fuzz::writeInput(data, size, "input.bin");
  try {
    const clhair::PlyStrands p = clhair::readCt2HairBin(bin, kMaxBytes);
    check(p, size);
    // every strand, kept or skipped, had its count; every kept point 28 bytes
    std::uint64_t points = 0;
    for (std::uint32_t s : p.hair.segments) points += std::uint64_t(s) + 1;
    CLHAIR_FUZZ_CHECK(4 + 4 * (p.hair.segments.size() + p.skippedStrands) + 28 * points <= size);
  } catch (const clhair::Error&) {
  }
  return 0;
}
