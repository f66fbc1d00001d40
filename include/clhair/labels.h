// labels.h — the labels hair models learn from, computed on the device from a frame's
// tangent and hair alpha layers (Renderer::labels; kernels/labels.cl):
//   angle       the strand's direction in the image modulo pi, counter-clockwise from +x
//               (y up), in [0, pi): NeuralHaircut's orientation map
//   confidence  the hair alpha times the sine of the angle between the strand and the
//               pixel's view ray (1 across the view, 0 pointing at the camera)
//   mask        hair alpha at least kLabelMaskAlpha
//   strandMap   HairStep's strand map, 3 per pixel: 1 where the mask holds a strand, then
//               its unit image direction (root to tip, x right, y up) mapped from [-1, 1] to
//               [0, 1]; 0 elsewhere
// angle, confidence and strandMap are 0 where no strand is. Per pixel, row-major, top row first.
// python/clhair/labels.py computes the same on the host with NumPy (the reference the tests compare
// with).
#pragma once

#include <cstdint>
#include <vector>

namespace clhair {

// Hair alpha at and above which a pixel counts as hair (the depth layer's own rule: hair at
// least half opaque holds the pixel).
constexpr float kLabelMaskAlpha = 0.5f;

struct HairLabels {
  int width = 0, height = 0;
  std::vector<float> angle, confidence;
  std::vector<std::uint8_t> mask;
  std::vector<float> strandMap;
};

}  // namespace clhair
