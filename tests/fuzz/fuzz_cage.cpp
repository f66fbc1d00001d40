// fuzz_cage.cpp — libFuzzer target for loadCageAnimation (host/io/cage_io.cpp).
//
// Any input must either be refused with a clhair::Error or read into a cage animation whose
// positions are exactly frames x vertices finite points within +-kMaxCoordinate, taking exactly the
// bytes the file has (24-byte header, 12 per point), and that writes back (saveCageAnimation) to
// the same bytes. Anything else is a finding.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include "clhair/animation.h"
#include "clhair/error.h"
#include "clhair/hair_mesh.h"
#include "fuzz_util.h"

namespace {
constexpr std::uint64_t kMaxBytes = 64ull << 20;
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = clhair::fuzz::writeInput(data, size, "input.cage");
  clhair::CageAnimation c;
  try {
    c = clhair::loadCageAnimation(path, kMaxBytes);
  } catch (const clhair::Error&) {
    return 0;
  }
  CLHAIR_FUZZ_CHECK(c.frames >= 1 && c.frames <= clhair::kMaxCageFrames);
  CLHAIR_FUZZ_CHECK(c.vertices >= 1 && c.vertices <= clhair::kMaxCageVertices);
  CLHAIR_FUZZ_CHECK(c.positions.size() == std::uint64_t(c.frames) * c.vertices);
  CLHAIR_FUZZ_CHECK(size == 24 + 12 * c.positions.size());
  CLHAIR_FUZZ_CHECK(12 * c.positions.size() <= kMaxBytes);
  for (const auto& p : c.positions) {
    CLHAIR_FUZZ_CHECK(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
    CLHAIR_FUZZ_CHECK(std::fabs(p.x) <= clhair::kMaxCoordinate &&
                      std::fabs(p.y) <= clhair::kMaxCoordinate &&
                      std::fabs(p.z) <= clhair::kMaxCoordinate);
  }
  // a file that reads writes back to the same bytes
  const std::string again = clhair::fuzz::workDir() + "/again.cage";
  clhair::saveCageAnimation(c, again);
  std::ifstream in(again, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CLHAIR_FUZZ_CHECK(bytes.size() == size && std::memcmp(bytes.data(), data, size) == 0);
  return 0;
}
