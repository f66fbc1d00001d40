// faint_groom.h — whether a strand file's groom draws as a faint ghost in a view: its fibres
// far thinner than a pixel and its hair covering a small share of its screen box (a scan
// subset of 100 strands, a guides-only export). The renderer then draws its centre hits at
// least kFaintHitDiameterPx wide with the alpha of its true width (DESIGN.md, "Grooms from
// the wild"); the CLI's notes name such a groom where the render cannot do that.
#pragma once

#include <cstddef>
#include <cstdint>

#include <glm/mat4x4.hpp>

#include "clhair/strand_groom.h"

namespace clhair {

// Fibres under a quarter of a pixel whose hair covers under 5 % of its screen box; dense
// grooms cover most of their box.
constexpr float kFaintThinPx = 0.25f;
constexpr double kFaintSparseShare = 0.05;
// The centre-hit diameter a faint groom is drawn with, pixels.
constexpr float kFaintHitDiameterPx = 1.0f;
// Strands projected at most (an even stride over the rest).
constexpr std::size_t kFaintMaxSampled = 20000;

// A pinhole view: view space x right, y up, z forward; pixel (cx + fx x / z, cy - fy y / z).
struct FaintView {
  float fx = 0.0f, fy = 0.0f, cx = 0.0f, cy = 0.0f;
  std::uint32_t width = 0, height = 0;
  bool operator==(const FaintView& o) const {
    return fx == o.fx && fy == o.fy && cx == o.cx && cy == o.cy && width == o.width &&
           height == o.height;
  }
};

struct FaintEstimate {
  bool seen = false;               // some of the groom lies in front of the view and on screen
  double widthPx = 0.0;            // the fibres' mean projected width, pixels
  double share = 0.0;              // projected fibre area over the screen box's, at most 1
  float boxW = 0.0f, boxH = 0.0f;  // the groom's screen box clipped to the image, pixels
  bool faint() const { return seen && widthPx < kFaintThinPx && share < kFaintSparseShare; }
};

// Each sampled segment's projected length times the fibre's projected width
// (appearance.strandWidth, world units), summed (children counted by their guides, the
// stride's skipped strands by the sampled ones), over the groom's projected bounding box of
// the sampled points clipped to the image.
FaintEstimate estimateFaint(const StrandGroom& groom, const glm::mat4& objToView,
                            const FaintView& view);

}  // namespace clhair
