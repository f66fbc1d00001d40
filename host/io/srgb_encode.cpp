// srgb_encode.cpp — see srgb_encode.h.
#include "io/srgb_encode.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

namespace clhair {

namespace {

constexpr std::uint32_t kOneBits = 0x3F800000u;  // 1.0f
constexpr std::uint32_t kInfBits = 0x7F800000u;  // +inf; above: NaN
constexpr int kBucketShift = 16;                 // table index: the upper 16 bits
constexpr std::size_t kBuckets = (kOneBits >> kBucketShift) + 1;

std::uint32_t bitsOf(float x) {
  std::uint32_t b;
  std::memcpy(&b, &x, sizeof(b));
  return b;
}

float floatOf(std::uint32_t b) {
  float x;
  std::memcpy(&x, &b, sizeof(x));
  return x;
}

struct Tables {
  // threshold[k]: bit pattern of the smallest float whose code is >= k (k = 1..255);
  // threshold[256]: beyond every float below 1, so the step loop stops there
  std::array<std::uint32_t, 257> threshold{};
  std::array<std::uint8_t, kBuckets> start{};  // the code at each bucket's first float

  Tables() {
    threshold[0] = 0;
    for (int k = 1; k <= 255; ++k) {
      // the code is non-decreasing in the bit pattern of non-negative floats: bisect
      std::uint32_t lo = threshold[k - 1], hi = kOneBits;  // code(lo) < k <= code(hi)
      if (srgbByteFormula(floatOf(lo)) >= k) {
        threshold[k] = lo;
        continue;
      }
      while (hi - lo > 1) {
        const std::uint32_t mid = lo + (hi - lo) / 2;
        (srgbByteFormula(floatOf(mid)) >= k ? hi : lo) = mid;
      }
      threshold[k] = hi;
    }
    threshold[256] = kOneBits;
    for (std::size_t i = 0; i < kBuckets; ++i)
      start[i] = srgbByteFormula(floatOf(static_cast<std::uint32_t>(i) << kBucketShift));
  }
};

const Tables& tables() {
  static const Tables t;
  return t;
}

std::uint8_t byteFromTables(const Tables& t, float x) {
  const std::uint32_t b = bitsOf(x);
  if (b >= kOneBits) return b <= kInfBits ? 255 : 0;  // >= 1 and +inf; NaN; negatives: below
  if (b == 0) return 0;
  int code = t.start[b >> kBucketShift];
  while (b >= t.threshold[code + 1]) ++code;
  return static_cast<std::uint8_t>(code);
}

}  // namespace

std::uint8_t srgbByteFormula(float x) {
  if (std::isnan(x)) return 0;
  x = std::min(std::max(x, 0.0f), 1.0f);
  const float v = x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
  return static_cast<std::uint8_t>(std::lround(v * 255.0f));
}

std::uint8_t srgbByte(float x) {
  // negative floats (sign bit set, also negative NaN) have bit patterns >= 0x80000000
  if (bitsOf(x) & 0x80000000u) return 0;
  return byteFromTables(tables(), x);
}

std::uint8_t alphaByte(float a) {
  if (!(a > 0.0f)) return 0;
  if (a >= 1.0f) return 255;
  return static_cast<std::uint8_t>(std::lround(a * 255.0f));
}

float srgbThreshold(int code) {
  return floatOf(tables().threshold[static_cast<std::size_t>(std::clamp(code, 1, 255))]);
}

void encodeSrgb8(const float* rgba, std::size_t pixels, int channels, std::uint8_t* out) {
  const Tables& t = tables();
  for (std::size_t p = 0; p < pixels; ++p, rgba += 4, out += channels) {
    for (int c = 0; c < 3; ++c)
      out[c] = (bitsOf(rgba[c]) & 0x80000000u) ? 0 : byteFromTables(t, rgba[c]);
    if (channels == 4) out[3] = alphaByte(rgba[3]);
  }
}

}  // namespace clhair
