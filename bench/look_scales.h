// look_scales.h — where the look's error lives in scale (clhair_bench --only look
// --look-scales): the FLIP left once every feature coarser than a radius is made exact, and
// the contrast of the hair in each octave of scale.
#ifndef CLHAIR_BENCH_LOOK_SCALES_H
#define CLHAIR_BENCH_LOOK_SCALES_H

#include <vector>

#include "clhair/image.h"

namespace clhair::bench {

// The box radii (pixels) the scale measurements use, an octave apart.
const std::vector<int>& lookScaleRadii();

// `test` with every masked pixel's channels scaled by the ratio of the reference's sum to the
// test's sum over the masked pixels of the (2r+1)^2 box around it. The result has the
// reference's mean over every such box and the test's own structure inside it: what the test
// would be if everything coarser than r pixels were exactly right. Its FLIP against the
// reference is therefore a lower bound for any change to the test that only moves features
// coarser than r (a smooth shading term, a lower-resolution map, an AO). Unmasked pixels
// are left as they are.
Image matchCoarserThan(const Image& ref, const Image& test, const std::vector<char>& mask,
                       int radius);

// The contrast of each octave over the masked pixels: for each radius r_k of
// lookScaleRadii(), the RMS of B_{k-1} - B_k, where B_k is the log luminance box-averaged
// over the masked pixels within r_k (B_{-1} the pixel's own), and last the standard
// deviation of the coarsest B. One value more than there are radii.
std::vector<double> octaveContrast(const Image& image, const std::vector<char>& mask);

// How well the two images' octave bands (as octaveContrast's) line up over the masked pixels:
// per band, the correlation sum(a b) / sqrt(sum a^2 sum b^2), 1 where the test's bright and dark
// features of that scale sit where the reference's do; NaN where either band is flat (RMS
// under 1e-4, e.g. a hair smaller than the box). One value more than there are radii.
std::vector<double> octaveCorrelation(const Image& ref, const Image& test,
                                      const std::vector<char>& mask);

}  // namespace clhair::bench

#endif
