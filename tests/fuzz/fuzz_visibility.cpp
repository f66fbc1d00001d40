// fuzz_visibility.cpp — libFuzzer target for readVisibility (host/io/visibility_io.cpp).
//
// A baked visibility file has one valid size (a 40-byte header and 64^3 cells of four
// floats), which random inputs almost never reach, so each input is read twice: as given,
// and expanded — its first 40 bytes as the header, the rest repeated to fill the table, the
// last byte of the input choosing how many bytes to drop from the end (0 keeps the size
// exact). Either read must be refused with a clhair::Error or give a bake whose table has
// the right length and only finite coefficients within the documented bound; an accepted
// bake must survive writeVisibility and read back identical. Anything else (another
// exception, a sanitizer report, a broken invariant) is a finding.
#include <cmath>
#include <cstdint>
#include <string>

#include "clhair/error.h"
#include "clhair/visibility.h"
#include "clhair/visibility_sh.h"
#include "fuzz_util.h"

namespace {

void check(const std::string& path) {
  clhair::VisibilityBake b;
  try {
    b = clhair::readVisibility(path);
  } catch (const clhair::Error&) {
    return;
  }
  CLHAIR_FUZZ_CHECK(b.sh.size() == std::size_t(CLH_VIS_CELLS) * CLH_VIS_COEFFS);
  CLHAIR_FUZZ_CHECK(b.strands > 0 && b.raysPerPoint > 0 && b.pointsPerCell > 0);
  for (float c : b.sh)
    CLHAIR_FUZZ_CHECK(std::isfinite(c) && std::fabs(c) <= clhair::kMaxVisibilityCoefficient);
  const std::string copy = clhair::fuzz::workDir() + "/copy.clhvis";
  clhair::writeVisibility(b, copy);
  const clhair::VisibilityBake r = clhair::readVisibility(copy);
  CLHAIR_FUZZ_CHECK(r.strands == b.strands && r.raysPerPoint == b.raysPerPoint &&
                    r.pointsPerCell == b.pointsPerCell);
  CLHAIR_FUZZ_CHECK(r.sh == b.sh);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  check(clhair::fuzz::writeInput(data, size, "input.clhvis"));
  if (size > clhair::kVisibilityHeaderBytes) {
    const std::size_t full =
        clhair::kVisibilityHeaderBytes + 4 * std::size_t(CLH_VIS_CELLS) * CLH_VIS_COEFFS;
    const std::size_t drop = data[size - 1] % 8;
    std::string bytes(reinterpret_cast<const char*>(data), clhair::kVisibilityHeaderBytes);
    const std::size_t body = size - clhair::kVisibilityHeaderBytes;
    while (bytes.size() < full - drop)
      bytes.push_back(
          static_cast<char>(data[clhair::kVisibilityHeaderBytes +
                                 (bytes.size() - clhair::kVisibilityHeaderBytes) % body]));
    check(clhair::fuzz::writeInput(reinterpret_cast<const std::uint8_t*>(bytes.data()),
                                   bytes.size(), "expanded.clhvis"));
  }
  return 0;
}
