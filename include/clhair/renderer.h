// renderer.h — the public entry point: render a Scene on a Device into a Frame.
//
// A Renderer owns the programs, the per-groom device resources (uploaded once per mesh)
// and the buffers sized to the render target. render() runs, for every groom in turn,
// lod -> scan + sizing -> strands -> shade -> composite over the opaque scene, and returns
// colour, alpha, depth and per-stage times taken from OpenCL profiling events.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "clhair/device.h"
#include "clhair/image.h"
#include "clhair/scene.h"

namespace clhair {

struct RenderOptions {
  int lod = -1;             // -1: as each groom says; 0: off; 1: on
  float lodLambdaScale = 1.0f;
};

struct StageTime {
  std::string stage;
  double ms = 0.0;  // sum of the stage's profiled dispatches in this frame
};

struct FrameStats {
  std::uint64_t strandsDrawn = 0;
  std::uint64_t segmentsDrawn = 0;
};

struct Frame {
  Image color;               // composited linear RGBA (alpha 1)
  std::vector<float> depth;  // view-space depth, +inf where nothing
  std::vector<StageTime> timings;
  FrameStats stats;

  double stageMs(const std::string& stage) const;
  double totalMs() const;
};

// Generated strands read back from the device (export-strands, tests).
struct StrandSet {
  std::vector<std::uint32_t> pointCounts;  // per strand
  std::vector<float> points;               // xyz per point, object space
  std::vector<float> tangents;             // xyz per point
  std::vector<float> w;                    // styling w per point
  std::vector<std::uint32_t> bundleOf;     // bundle of each strand
};

class Renderer {
 public:
  explicit Renderer(Device device);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  Frame render(const Scene& scene, const RenderOptions& options = {});

  // Runs the strand kernel in export mode for `mesh` at full detail (no LOD).
  StrandSet generateStrands(const HairMesh& mesh);

  const Device& device() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace clhair
