// bake_scene.h — the Embree scenes the visibility bake traces (visibility_bake.cpp): every
// exported strand segment a round linear curve in Morton order of its midpoint, with a
// filter that counts the distinct strands a ray passes, and the occluders' triangles.
#pragma once

#include <embree3/rtcore.h>

#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "clhair/error.h"
#include "groom/visibility_bake.h"

namespace clhair {

// A ray's context: Embree hands it to the curve filter, which counts the distinct strands
// the ray passes (a tube can report its entry and exit, and a ray can cross a strand at a
// joint of two segments). The ray is traced as an occlusion query: the filter rejects every
// hit until `cap` strands are counted (so traversal goes on through every fibre) and then
// accepts one, which ends the traversal. The count does not depend on the order Embree
// visits the hits in, so this is the count of an intersection query that rejects every hit,
// capped; `cap` is the count past which the ray's events are clamped anyway.
constexpr unsigned kPacket = 16;  // rays per Embree packet (one point's rays go together)

struct CountContext {
  RTCIntersectContext base;  // first member: Embree passes &base
  const std::uint32_t* strandOfSegment = nullptr;
  std::uint32_t own = 0;  // the rays' own strand
  // per ray of the packet (the ray's id): the cap, the count, the strands counted
  std::uint32_t cap[kPacket];
  std::uint32_t count[kPacket];
  std::uint32_t seen[kPacket][kMaxEventsLimit];
};

// The curve filter of the strand count (CountContext).
void countStrands(const RTCFilterFunctionNArguments* args);

struct EmbreeScene {
  RTCDevice device = nullptr;
  RTCScene hair = nullptr, head = nullptr;
  float* vertices = nullptr;
  ~EmbreeScene() {
    if (hair) rtcReleaseScene(hair);
    if (head) rtcReleaseScene(head);
    if (device) rtcReleaseDevice(device);
    std::free(vertices);
  }
  void check(const char* what) const {
    const RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE)
      throw Error(std::string("visibility bake: Embree failed while ") + what + " (error " +
                  std::to_string(static_cast<int>(e)) + ")");
  }
};

// Creates the device and both scenes of `es` and fills them (not committed): the strands of
// `s` as fibres of `fibreRadius`, and the occluders. pointStrand: each exported point's
// strand; strandOf: each segment's (Embree's primID) strand.
void buildBakeScene(EmbreeScene& es, const StrandSet& s, float fibreRadius,
                    const std::vector<glm::vec3>& triPositions,
                    const std::vector<std::uint32_t>& triIndices,
                    std::vector<std::uint32_t>& pointStrand, std::vector<std::uint32_t>& strandOf);

}  // namespace clhair
