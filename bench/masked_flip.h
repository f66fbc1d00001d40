// masked_flip.h — mean FLIP over a mask's pixels, the benchmark's measure of an image against a
// reference over the hair (defined in harness.cpp; lod_far.cpp takes it without the harness).
#pragma once

#include <vector>

#include "clhair/image.h"

namespace clhair::bench {

// Mean FLIP of `test` against `ref` over the mask's pixels (0 where the mask is empty).
double maskedFlip(const Image& ref, const Image& test, const std::vector<char>& mask);

}  // namespace clhair::bench
