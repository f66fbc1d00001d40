// srgb_encode.h — linear float colour to 8-bit sRGB codes, by table, exactly as the formula.
//
// The 8-bit writers store round(255 * srgb(clamp(x, 0, 1))) with the sRGB curve (12.92 x up to
// 0.0031308, else 1.055 x^(1/2.4) - 0.055) evaluated in float (srgbByteFormula). That is one
// powf per value. srgbByte gives the same byte for every float without it: the code is a step
// function of x, so the smallest float that reaches each code 1..255 (found once by bisection
// over the ordered bit patterns of the non-negative floats) decides it, and a table indexed by
// the upper 16 bits of x gives the code at the start of x's bucket, from which at most a step
// or two of threshold comparisons remain. NaN and values <= 0 give 0, values >= 1 give 255,
// as the formula does. The tables are built on first use (thread-safe) from the formula itself,
// so they agree with it on every machine. tests/test_image_io.cpp checks the equality on a
// dense sample and around every threshold.
#pragma once

#include <cstddef>
#include <cstdint>

namespace clhair {

// The reference: the byte the formula gives (NaN: 0).
std::uint8_t srgbByteFormula(float x);

// The same byte through the tables.
std::uint8_t srgbByte(float x);

// The same as the writers store alpha: round(255 * clamp(a, 0, 1)), NaN: 0.
std::uint8_t alphaByte(float a);

// Interleaved RGBA floats (linear, alpha straight) of `pixels` pixels to `channels` (3 or 4)
// bytes per pixel: sRGB colour and, with 4, linear alpha.
void encodeSrgb8(const float* rgba, std::size_t pixels, int channels, std::uint8_t* out);

// The smallest non-negative float whose formula byte is `code` (1..255): the thresholds.
float srgbThreshold(int code);

}  // namespace clhair
