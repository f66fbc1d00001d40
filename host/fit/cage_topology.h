// cage_topology.h — the root layer of the fitted hair mesh: one quad per cluster on the
// scalp chart, with corners shared between neighbouring clusters where their roots touch.
//
// A cluster's quad is centred on the mean of its chart roots and spans sqrt(3) standard
// deviations along its axes (a uniform square of side 2a has standard deviation a/sqrt(3),
// so a square cluster gets exactly its own square). The axes are the chart's x and y unless
// the cluster is clearly elongated across them, then its principal axes. Corners of
// different clusters that lie within a third of the lattice spacing of each other, and whose
// clusters have compatible shapes (not across a parting), are welded into one vertex at
// their mean; a weld that would fold or shrink a quad is undone. Faces are counter-clockwise
// on the chart, corner k at bilinear (s, t) = (0,0), (1,0), (1,1), (0,1).
#pragma once

#include <array>
#include <vector>

#include <glm/vec2.hpp>

#include "fit/bundle_clusters.h"

namespace clhair::fit {

struct CageTopology {
  std::vector<glm::vec2> vertexChart;                // per vertex, chart position
  std::vector<std::array<int, 4>> faces;             // per cluster
  std::vector<std::array<glm::vec2, 4>> ownCorners;  // per face, before welding
  std::vector<std::array<glm::vec2, 2>> axes;        // per face, chart unit axes (s, t)
  std::vector<std::vector<int>> vertexCorners;       // per vertex: 4 * face + corner
  int weldedVertices = 0;                            // vertices shared by 2+ faces
};

// minExtent: smallest half side of a quad (chart metres). weldShapeLimit: largest shape
// distance (in lattice cells, as clustering measures it) across which corners are welded.
CageTopology buildCageTopology(const Clusters& clusters, const std::vector<glm::vec2>& chartRoots,
                               float minExtent, float shapeWeight, float shapeScale,
                               float weldShapeLimit);

// Bilinear coordinates of chart point p in quad q (corner order as above), by Newton steps
// from the centre; not clamped.
glm::vec2 inverseBilinear(const std::array<glm::vec2, 4>& q, const glm::vec2& p);

}  // namespace clhair::fit
