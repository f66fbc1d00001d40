// fuzz_tressfx.cpp — libFuzzer target for readTressFx (host/io/tressfx_read.cpp).
//
// Any input must either be refused with a clhair::Error or read into strands that all have
// the header's vertex count (2 or more), finite points and finite strand uv, taking no
// more points than the file has bytes for. resampleStrands on those strands must keep every
// root and tip exactly, and the strands written back as TressFX 4.0 (writeTressFx) must
// read back identical. Anything else is a finding.
#include <cmath>
#include <cstdint>
#include <string>

#include "clhair/error.h"
#include "fuzz_util.h"
#include "io/tressfx.h"

namespace {
constexpr std::uint64_t kMaxBytes = 64ull << 20;
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = clhair::fuzz::writeInput(data, size, "input.tfx");
  clhair::TressFxHair t;
  try {
    t = clhair::readTressFx(path, kMaxBytes);
  } catch (const clhair::Error&) {
    return 0;
  }
  const clhair::CyHair& h = t.hair;
  CLHAIR_FUZZ_CHECK(!h.segments.empty());
  const std::uint64_t perStrand = std::uint64_t(h.segments[0]) + 1;
  CLHAIR_FUZZ_CHECK(perStrand >= 2);
  for (std::uint32_t s : h.segments) CLHAIR_FUZZ_CHECK(s + std::uint64_t(1) == perStrand);
  const std::uint64_t points = perStrand * h.segments.size();
  CLHAIR_FUZZ_CHECK(h.points.size() == 3 * points);
  for (float v : h.points) CLHAIR_FUZZ_CHECK(std::isfinite(v));
  CLHAIR_FUZZ_CHECK(t.strandUv.empty() || t.strandUv.size() == 2 * h.segments.size());
  for (float v : t.strandUv) CLHAIR_FUZZ_CHECK(std::isfinite(v));
  CLHAIR_FUZZ_CHECK(h.thickness.empty() && h.transparency.empty() && h.colors.empty());
  // 3.x stores 12 bytes per point after a 296-byte header, 4.x 16 after 160.
  const bool v3 = t.version < 4.0f;
  CLHAIR_FUZZ_CHECK((v3 ? 296 : 160) + (v3 ? 12 : 16) * points <= size);
  CLHAIR_FUZZ_CHECK(h.trailingBytes <= size);

  const std::string copy = clhair::fuzz::workDir() + "/copy.tfx";
  clhair::TressFxHair w;
  w.hair = clhair::resampleStrands(h, static_cast<std::uint32_t>(perStrand));
  w.strandUv = t.strandUv;
  for (std::size_t i = 0; i < h.points.size(); ++i) {
    const std::size_t k = (i / 3) % perStrand;
    if (k == 0 || k == perStrand - 1) CLHAIR_FUZZ_CHECK(w.hair.points[i] == h.points[i]);
  }
  w.hair.points = h.points;  // the writer must keep arbitrary finite points bit for bit
  try {
    clhair::writeTressFx(w, copy);
  } catch (const clhair::Error&) {
    return 0;  // only a file of 4 GiB or more is refused, beyond kMaxBytes
  }
  const clhair::TressFxHair r = clhair::readTressFx(copy, kMaxBytes);
  CLHAIR_FUZZ_CHECK(r.version == 4.0f);
  CLHAIR_FUZZ_CHECK(r.hair.segments == h.segments);
  CLHAIR_FUZZ_CHECK(r.hair.points == h.points);
  CLHAIR_FUZZ_CHECK(r.strandUv == t.strandUv);
  CLHAIR_FUZZ_CHECK(r.hair.trailingBytes == 0);
  return 0;
}
