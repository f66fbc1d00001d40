// fuzz_cache_entry.cpp — libFuzzer target for decodeCacheEntry (host/cl/binary_cache.cpp), the
// reader of the kernel cache's entry files.
//
// Any bytes must either be refused or decode to a payload that encodes back (encodeCacheEntry)
// to exactly those bytes; an entry of one key never decodes under another. Anything else (a
// crash, a read past the input, a payload that does not round-trip) is a finding.
#include <cstdint>
#include <string>
#include <vector>

#include "cl/binary_cache.h"
#include "fuzz_util.h"

namespace {
// the key the seeds are written for (corpus/cache_entry), and another
const std::string kKey = "0123456789abcdef0123456789abcdef.clbin";
const std::string kOther = "0123456789abcdef0123456789abcdee.clbin";
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  std::string why;
  const auto payload = clhair::decodeCacheEntry(bytes, kKey, &why);
  if (!payload) {
    CLHAIR_FUZZ_CHECK(!why.empty());
    return 0;
  }
  CLHAIR_FUZZ_CHECK(clhair::encodeCacheEntry(kKey, *payload) == bytes);
  CLHAIR_FUZZ_CHECK(!clhair::decodeCacheEntry(bytes, kOther));
  return 0;
}
