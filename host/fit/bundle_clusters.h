// bundle_clusters.h — strands grouped into bundles: k-means over root position on the scalp
// chart and strand shape.
//
// Each strand is a point (x, y, s1 .. s12): its root on the chart divided by the lattice
// spacing h, and its positions at 1/4, 1/2, 3/4 and all of its length relative to its root,
// scaled to the median strand length (so length variation does not split bundles), times
// shapeWeight / shapeScale. The centres start on a square lattice of spacing h over
// the chart (h chosen so that about `target` lattice cells hold roots), so the clusters
// start as squares that tile the scalp. The root part of every centre stays at its cell's
// centre while a few k-means iterations update the shape part and reassign strands: the
// clusters keep tiling the scalp like the cells, except where the shape changes (a
// parting, the edge of a clump), where the boundary moves to the change. Clusters left with
// fewer than a quarter of the mean strand count are merged into their nearest neighbour.
#pragma once

#include <cstddef>
#include <vector>

#include <glm/vec2.hpp>

#include "fit/fit_strands.h"

namespace clhair::fit {

struct Clusters {
  int count = 0;
  float spacing = 0.0f;           // lattice spacing h, chart metres (0: all roots coincide)
  std::vector<int> label;         // per strand, 0..count-1
  std::vector<int> members;       // per cluster: strands
  std::vector<glm::vec2> centre;  // per cluster: mean chart root
  std::vector<float> shape;       // per cluster: mean shape feature (kShapeDims floats each)
};

constexpr int kShapeDims = 12;

// Shape features of every strand (kShapeDims floats each), relative to its root.
std::vector<float> shapeFeatures(const FitStrands& strands, int threads);

Clusters clusterStrands(const std::vector<glm::vec2>& chartRoots, const std::vector<float>& shape,
                        int target, float shapeWeight, float shapeScale, int threads);

}  // namespace clhair::fit
