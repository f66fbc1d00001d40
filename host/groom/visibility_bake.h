// visibility_bake.h — the offline bake of a groom's spherical visibility with Embree
// (Kulikov 2025, "precomputed self-shadowing"; `clhair bake-visibility`).
//
// Input: the groom's strands as the kernels draw them at full detail (object space, with the
// u, v, w their G-buffer words carry), the fibre radius in object units, and the opaque
// occluders (the head: the scene's spheres and meshes) as triangles in the same space.
// Sample points are binned by the words' cell (visibility_sh.h); each cell keeps up to
// `pointsPerCell` of its points, chosen by a hash (a uniform sample over the strands that
// pass through it). From every sample point `raysPerPoint` stratified directions are traced
// twice, in packets of the point's rays: against the occluders (the distance to the head)
// and then, up to that distance, against the strands as Embree round linear curves, one
// curve per segment stored in Morton order of the segment midpoints (cache-friendly vertex
// gathers), counting every other strand the ray passes (its own strand is skipped) in an
// occlusion query whose filter rejects hits until the count reaches the cap past which it
// no longer matters. A ray that reaches the head counts
// HAIR_MAX_SCATTER_EVENTS more (the head is opaque), a ray's count is capped at
// VisibilityBakeOptions::maxEvents, and a ray that meets nothing counts
// -HAIR_MAX_SCATTER_EVENTS (Kulikov's miss bias). The counts are projected onto L1 SH and averaged
// over the cell's points. Output: a VisibilityBake (include/clhair/visibility.h). A word's w is
// interpolated along its segment, so cells between a strand's points are filled by linear
// interpolation along w between the baked cells of their (u, v) column (the nearest one beyond its
// ends); columns no point reached stay zero (visibility 1). Deterministic for a given input and
// options (per-point seeds; the threads only split the points).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "clhair/strand_groom.h"
#include "clhair/visibility.h"

namespace clhair {

constexpr std::uint32_t kMaxEventsLimit = 32;  // the most a ray can count (its filter's memory)
constexpr std::uint32_t kTransmittanceAbsorptions = 4;
// The absorptions the transmittance study mode evaluates (the scene's default is 0.5).
constexpr float kTransmittanceAbsorption[kTransmittanceAbsorptions] = {0.125f, 0.25f, 0.5f, 1.0f};

struct VisibilityBakeOptions {
  // The defaults come from a study against the groom's true transmittance (docs/scene-format.md,
  // "Visibility bake estimator"): the L1 fit, not the ray count, dominates the error, so 16
  // rays per point lose under 1 % of accuracy against 32, and a cap of 10 events is closer to
  // the transmittance at the scene's default absorption (0.5) than a cap of 20, while each ray
  // stops earlier.
  std::uint32_t raysPerPoint = 16;
  std::uint32_t pointsPerCell = 4;
  std::uint32_t maxEvents = 10;  // a ray's count is clamped here (1..kMaxEventsLimit)
  unsigned threads = 0;          // 0: every hardware thread
  // How a cell's rays get their directions: PerPoint (default) gives every point its own
  // stratified set of R, rotated by the point; PerCell deals one set of n x R directions out
  // to the cell's n points, so their union covers the sphere evenly (measured no better
  // overall: docs/scene-format.md, "Visibility bake estimator").
  enum class Directions { PerPoint, PerCell };
  Directions directions = Directions::PerPoint;
  // Bake only the occupied cells whose hash is 0 modulo cellStride and leave every other
  // cell zero (no interpolation along w): a sample of the table for estimator studies.
  std::uint32_t cellStride = 1;
  // Study mode (`--transmittance-out`): every point traces the same raysPerPoint spherical
  // Fibonacci directions (k + 1/2 spacing, no rotation) and the stats keep, per cell,
  // direction and absorption A of kTransmittanceAbsorption, the points' mean transmittance
  // exp(-A x events) of the ray model before any L1 projection: the reference the estimator
  // study compares bakes' exp(-A x max(0, SH)) against. Needs PerPoint directions.
  bool transmittance = false;
};

// Where a bake's time goes (`clhair bake-visibility --verbose`). cpuSeconds is the whole
// process's CPU time over the phase (every thread, Embree's and the OpenCL runtime's too).
// For the tracing phase, `threads` workers split the points; waitSeconds is the time they
// were runnable but waiting for a core (the kernel's schedstat: other processes' load) and
// the rest of threads x wall that is neither CPU nor waiting is time they were blocked or
// idle (-1: the kernel does not report it).
struct BakePhase {
  std::string name;
  double wallSeconds = 0.0;
  double cpuSeconds = 0.0;
  unsigned threads = 0;  // 0: not a split phase
  double waitSeconds = -1.0;
};

struct VisibilityBakeStats {
  std::uint64_t cells = 0;   // cells holding at least one sample point
  std::uint64_t points = 0;  // sample points traced
  std::uint64_t rays = 0;
  double meanEvents = 0.0;  // over the rays that hit something
  std::vector<BakePhase> phases;
  // Study mode only: [absorption][cell][direction] (kTransmittanceAbsorptions x CLH_VIS_CELLS
  // x raysPerPoint), zero for cells without points.
  std::vector<float> transmittance;
};

// Wall and process CPU time from construction; `finish` appends the phase to `stats` (if
// any) and starts the next one.
class BakePhaseTimer {
 public:
  explicit BakePhaseTimer(VisibilityBakeStats* stats);
  BakePhase& finish(const std::string& name);

 private:
  VisibilityBakeStats* stats_;
  BakePhase scratch_;
  double wall0_ = 0.0, cpu0_ = 0.0;
};

// `groomStrands` is written into the bake (checked against the groom when a scene loads it).
VisibilityBake bakeVisibility(const StrandSet& strands, float fibreRadius,
                              const std::vector<glm::vec3>& triPositions,
                              const std::vector<std::uint32_t>& triIndices,
                              std::uint32_t groomStrands, const VisibilityBakeOptions& options,
                              VisibilityBakeStats* stats = nullptr);

// Bakes groom `groom` of scene `s` (`clhair bake-visibility`): its strands at full detail as
// the kernels generate or draw them (exported through `r`), in its object space, against
// itself and the scene's spheres (tessellated) and meshes as the head; planes are left out
// (a floor would shadow every downward direction). The fibre radius is half the groom's
// strand width in object units.
VisibilityBake bakeGroomVisibility(Renderer& r, const Scene& s, std::size_t groom,
                                   const VisibilityBakeOptions& options,
                                   VisibilityBakeStats* stats = nullptr);

// The L1 SH coefficients (Y00, Y1-1, Y10, Y11) of `count` values f_k at unit directions
// dirs[3k..3k+2], each standing for 4 pi / count of the sphere: the Monte Carlo projection the
// bake uses, exposed for the round-trip test.
void projectL1(const float* dirs, const float* values, std::uint32_t count, float out[4]);

// `count` stratified unit directions (a spherical Fibonacci set rotated by `seed`), xyz each.
void sphereDirections(std::uint32_t count, std::uint32_t seed, float* out);

// The study mode's fixed directions: z_k = 1 - (2k + 1) / count, azimuth (k + 1/2) times the
// golden angle (scripts/compare-visibility.py evaluates the same set).
void fibonacciDirections(std::uint32_t count, float* out);

}  // namespace clhair
