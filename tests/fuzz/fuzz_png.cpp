// fuzz_png.cpp — libFuzzer target for checkPng (host/io/png_check.cpp), the walk every PNG
// takes before a decoder sees it.
//
// Any bytes must either be refused with a clhair::Error of one line, or pass; a pass means a
// signature, an IHDR of at most 2^24 pixels, and an image data stream that inflates to exactly
// the size the header declares. Anything else (a crash, a read past the input, an undefined
// shift or overflow) is a finding.
#include <cstdint>
#include <string>

#include "clhair/error.h"
#include "fuzz_util.h"
#include "io/png_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    clhair::checkPng(bytes, "input.png", std::uint64_t(1) << 24);
  } catch (const clhair::Error& e) {
    CLHAIR_FUZZ_CHECK(std::string(e.what()).find('\n') == std::string::npos);
    return 0;
  }
  CLHAIR_FUZZ_CHECK(clhair::looksLikePng(bytes));
  CLHAIR_FUZZ_CHECK(size >= 8 + 25 + 12 + 12);  // signature, IHDR, an IDAT, IEND
  return 0;
}
