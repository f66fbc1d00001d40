// cage_layers.h — the layers of the fitted hair mesh: where each input strand sits in its
// bundle, and every vertex's position on every layer.
//
// Layer l of a strand is its point at arc length l / (L - 1) of its *full* length: the
// length a strand at that root would have without length variation: at each vertex the
// mean length of its faces' strands times the top of all strands' lengths relative to that
// mean (from their 10th and 90th percentiles, exact for uniformly varied lengths),
// interpolated bilinearly, never less than the strand's own. Shorter strands simply end before the
// upper layers. This keeps a layer at one place along the hair for long and short strands alike,
// which is what the generator assumes when it shortens a strand by cutting its base curve.
//
// First every cluster's cross-section on every layer gives a quad: its centre, and its
// principal axes in the plane across the bundle scaled by sqrt(3) standard deviations. The
// axes are carried from layer to layer (each layer takes the principal axis, of the four
// signed choices, nearest to the previous layer's, and keeps the frame's handedness), so a
// bundle never flips or swaps its corners between layers. Corners welded on the root layer
// average their clusters' quads. Then, layer by layer, every vertex is refined by least
// squares: the bilinear interpolation of its face's corners at each strand's (s, t) should
// meet that strand's point on the layer, with a weak pull toward the principal-axis quad
// where strands are few (conjugate gradients on the sparse normal equations).
#pragma once

#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "fit/base_curve.h"
#include "fit/bundle_clusters.h"
#include "fit/cage_topology.h"
#include "fit/fit_strands.h"
#include "fit/scalp_chart.h"

namespace clhair::fit {

class HeadSurface;

struct StrandPlacement {
  std::vector<int> face;            // per strand
  std::vector<glm::vec2> st;        // per strand, bilinear coordinates clamped to [0, 1]
  std::vector<float> fullLength;    // per strand
  std::vector<float> vertexLength;  // per vertex: the full length there
};

StrandPlacement placeStrands(const FitStrands& strands, const Clusters& clusters,
                             const CageTopology& topo, const std::vector<glm::vec2>& chartRoots,
                             int threads);

// The full length at every vertex and of every strand (see above), from `strands`' lengths.
void fullLengths(const FitStrands& strands, const CageTopology& topo, StrandPlacement& place);

// Arc length along every strand of its point on every layer (strands * layers; -1: the
// strand ends before that layer): layer l at l / (L - 1) of the strand's full length. A
// strand counts on layers up to 2 % of its full length past its tip, 15 % when `carried`
// (fitCageLayers is given base curves to carry it on).
std::vector<float> linearLayerArcs(const FitStrands& strands, const StrandPlacement& place,
                                   int layers, bool carried);

// Positions layer-major (layers * vertices); `previous`: base curves of an earlier fit that
// carry strands past their tips (null: straight on); `head` moves the root layer onto it.
std::vector<glm::vec3> fitCageLayers(const FitStrands& strands, const Clusters& clusters,
                                     const CageTopology& topo, const ScalpChart& chart,
                                     const StrandPlacement& place,
                                     const std::vector<float>& layerArc, int layers,
                                     const BaseCurves* previous, const HeadSurface* head,
                                     int threads);

}  // namespace clhair::fit
