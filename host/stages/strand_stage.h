// strand_stage.h — binds and launches strands_raster / strands_opacity / strands_export
// (kernels/strands.cl) of a hair mesh: strands in the device's launch shape
// (dispatchStrands). The raster kernel is built per MSAA sample count (and with counters
// for statistics runs); the dispatch follows the chosen sizing mode.
#pragma once

#include <algorithm>
#include <cstdint>
#include <map>
#include <string>

#include "cl/dispatch.h"
#include "clhair/error.h"
#include "clhair/gpu_types.h"
#include "clhair/raster_core.h"

namespace clhair {

// The build option that keeps one entry point of a strand program (CLH_ENTRY, raster_core.h).
inline std::string entryOption(int entry) { return " -DCLH_ENTRY=" + std::to_string(entry); }

// The point lists of per-point shading (PointStage, kernels/points.cl): what the strand
// kernels' point pass reads (the marked points and their ranks) and writes (the records).
struct PointLists {
  const cl::Buffer* bits = nullptr;     // uint per 32 points of the groom's point space
  const cl::Buffer* offsets = nullptr;  // uint per bitmap word, then the total
  cl::Buffer* records = nullptr;        // ClhPointGpu per slot
  std::uint32_t words = 0;              // bitmap words
  std::uint32_t capacity = 0;           // records
};

// Where a strand pass draws: shared by the hair-mesh and explicit strand kernels.
struct StrandRaster {
  const cl::Buffer* view = nullptr;        // ClhViewGpu
  const cl::Buffer* sceneDepth = nullptr;  // float per pixel
  cl::Buffer* gbuffer = nullptr;           // ulong per pixel, msaa + 1 layers
  cl::Buffer* counters = nullptr;          // uint[4], written when stats
  std::size_t pixels = 0;
  int msaa = 1;
  bool stats = false;
  DispatchMode mode = DispatchMode::ReadBack;
  std::uint32_t strands = 0;  // ReadBack: the exact total; otherwise an upper bound
  int layers = 0;             // layers of `gbuffer` (0: msaa + 1)
  bool ids = false;           // also write the identity layer (layer msaa + 1, MSAA 1)
  // also write the sample identity layers (layers msaa + 1 .. 2 msaa, per-point shading)
  bool pointIds = false;
  // the point pass of per-point shading: nothing drawn; the marked points' records written
  const PointLists* points = nullptr;
  // the curve pass of hair linking: only the strands flagged in linkFlags (linkWords uints)
  // draw their centre lines into layers CLH_LAYER_CURVE and CLH_LAYER_CURVE_ID
  bool curve = false;
  // coverage mode (clhair/coverage.h): trapezoids into three depth-ordered layers and the
  // additive coverage plane (layers 0..3, MSAA 1)
  bool cover = false;
  const cl::Buffer* linkFlags = nullptr;
  std::uint32_t linkWords = 0;
  // several views (StrandStage::rasterViews): from one view's slice of sceneDepth (floats)
  // and of gbuffer (words) to the next's; 0: packed (pixels, pixels * (msaa + 1))
  std::uint64_t depthStride = 0, gbufferStride = 0;

  std::uint64_t gbufferBytes() const {
    return static_cast<std::uint64_t>(pixels) *
           static_cast<std::uint64_t>(layers > 0 ? layers : msaa + 1) * 8u;
  }
  // Refuses the combinations no raster kernel is built for (both strand stages call it).
  void check() const {
    if (msaa != 1 && msaa != 2 && msaa != 4 && msaa != 8)
      throw Error("MSAA must be 1, 2, 4 or 8 samples, not " + std::to_string(msaa));
    if ((ids || curve) && msaa != 1)
      throw Error("strand identities need MSAA 1, not " + std::to_string(msaa));
    if (cover && (msaa != 1 || ids || curve))
      throw Error("the coverage raster draws one sample per pixel without strand identities");
    if ((pointIds || points) && (ids || curve || cover || (pointIds && points)))
      throw Error("per-point shading's passes draw the plain lines raster");
  }
  // for timings
  std::string stage() const { return curve ? "link" : (points ? "points" : "strands"); }
  // options() plus the entry point (CLH_ENTRY, raster_core.h): the plain or persistent raster
  std::string entryOptions(bool persistent) const {
    return options() + entryOption(persistent ? CLH_ENTRY_RASTER_PERSISTENT : CLH_ENTRY_RASTER);
  }
  std::string options() const {
    return "-DCLH_MSAA=" + std::to_string(msaa) + (stats ? " -DCLH_RASTER_STATS=1" : "") +
           (curve ? " -DCLH_RASTER_CURVE=1" : (ids ? " -DCLH_STRAND_ID=1" : "")) +
           (cover ? " -DCLH_RASTER_COVER=1" : "") + (pointIds ? " -DCLH_POINT_ID=1" : "") +
           (points ? " -DCLH_RASTER_POINTS=1" : "");
  }
  // Binds the arguments the curve pass or the point pass take after the common ones.
  void bindExtras(KernelArgs& a) const {
    if (curve)
      a.buffer("source strands", *linkFlags, std::uint64_t(linkWords) * sizeof(cl_uint))
          .value("source strand words", static_cast<cl_uint>(linkWords));
    if (points)
      a.buffer("marked points", *points->bits, std::uint64_t(points->words) * sizeof(cl_uint))
          .buffer("point ranks", *points->offsets,
                  (std::uint64_t(points->words) + 1) * sizeof(cl_uint))
          .value("point words", static_cast<cl_uint>(points->words))
          .buffer("point records", *points->records,
                  std::uint64_t(std::max<std::uint32_t>(points->capacity, 1)) *
                      sizeof(gpu::ClhPointGpu))
          .value("point capacity", static_cast<cl_uint>(points->capacity));
  }
};

// The deep-opacity accumulation of one light (ShadowMaps): the light's view and maps.
struct OpacityDraw {
  const cl::Buffer* lightView = nullptr;    // ClhViewGpu
  const cl::Buffer* opaqueDepth = nullptr;  // float per texel (all slots)
  const cl::Buffer* shadow = nullptr;       // one ClhShadowGpu
  const cl::Buffer* hairDepth = nullptr;    // float per texel (all slots)
  cl::Buffer* opacity = nullptr;            // uint per texel and layer (all slots)
  std::size_t texels = 0;                   // all slots
};

// The motion pass of a deforming groom (kernels/strands.cl, strands_explicit.cl built with
// CLH_RASTER_MOTION), run right after its raster pass over the same G-buffer and depth.
struct MotionDraw {
  const cl::Buffer* params = nullptr;  // one ClhMotionGpu: previous transform and camera
  cl::Buffer* motion = nullptr;        // ulong per pixel, cleared to all ones
};

// A still's strands assembled once and kept (strands_store), then drawn in each of its
// passes (strands_raster_stored): the LOD records and scan they were assembled with, the
// first stored point of each bundle's strands (C points per strand), the points and
// tangents, and the root coordinates per draw index. The owner (a groom instance) fills
// the records, scan and bases; StrandStage::store and rasterStored bind them.
struct StoredStrands {
  cl::Buffer lod, offsets, pointBase, points, tangents, uvs;
  std::size_t lodCap = 0, offsetsCap = 0, baseCap = 0, pointCap = 0, tangentCap = 0, uvCap = 0;
  std::uint64_t pointCount = 0;  // points stored
  std::uint32_t strands = 0;     // strands stored: the records' drawn total
  std::uint64_t still = 0;       // the still whose strands these are (0: none)
  bool fits = false;             // false: that still's strands exceed the device's memory
};

class StrandStage {
 public:
  explicit StrandStage(Device::Impl& dev);

  struct Inputs {
    const cl::Buffer* groom = nullptr;      // ClhGroomGpu
    const cl::Buffer* bundles = nullptr;    // ClhBundle[bundleCount]
    const cl::Buffer* vertices = nullptr;   // ClhMeshVertex[vertexTotal]
    const cl::Buffer* lod = nullptr;        // ClhLodRecord[bundleCount]
    const cl::Buffer* offsets = nullptr;    // uint[clh_lod_offsets_length(bundleCount)]
    const cl::Buffer* rootsQuad = nullptr;  // float2[rootSetSize]
    const cl::Buffer* rootsTri = nullptr;   // float2[rootSetSize]
    std::uint32_t bundleCount = 0;
    std::size_t vertexTotal = 0, rootSetSize = 0;
  };
  void raster(const Inputs& in, const StrandRaster& r, Profiler* profiler);
  void opacity(const Inputs& in, const OpacityDraw& o, std::uint32_t strands, Profiler* profiler);
  // Several views of one assembly (strands_raster_views): r.view is the view the LOD was
  // chosen in (sizes every view), r.sceneDepth and r.gbuffer hold `count` slices in view
  // order, r.depthStride and r.gbufferStride apart, viewGrooms and views one record per
  // view. Read-back or over-launch sizing.
  void rasterViews(const Inputs& in, const StrandRaster& r, const cl::Buffer& viewGrooms,
                   const cl::Buffer& views, std::uint32_t count, Profiler* profiler);
  // The motion pass: `previous` holds the layer vertices of the previous frame (as many as
  // in.vertices); r is the raster pass just run (read-back sizing: r.strands exact).
  void motion(const Inputs& in, const cl::Buffer& previous, const MotionDraw& m,
              const StrandRaster& r, Profiler* profiler);
  // Assembles the strands of in.lod / in.offsets (a StoredStrands' copies) into `s`.
  void store(const Inputs& in, StoredStrands& s, Profiler* profiler);
  // Draws the strands `s` holds (in.lod / in.offsets: its copies) as raster() draws them
  // from the same records: the plain or identity raster, sized by s.strands.
  // subset > 1: the pass draws one strand in `subset`, widened (strands_raster_stored),
  // the subset chosen by `pass`.
  void rasterStored(const Inputs& in, const StrandRaster& r, const StoredStrands& s,
                    Profiler* profiler, std::uint32_t subset = 1, std::uint32_t pass = 0);
  // points/tangents: float4 * CLH_MAX_CONTROL_POINTS per strand; counts: uint per strand.
  void exportStrands(const Inputs& in, std::uint32_t strands, cl::Buffer& points,
                     cl::Buffer& tangents, cl::Buffer& counts, Profiler* profiler);

 private:
  void bindGroom(KernelArgs& a, const Inputs& in);
  // groom, view, geometry, scene depth, G-buffer, counters, strand base and stride, and the
  // curve or point pass's extras (strands_raster and strands_raster_stored); returns the
  // strand base's index
  cl_uint bindRaster(KernelArgs& a, const Inputs& in, const StrandRaster& r);
  void bindStored(KernelArgs& a, const Inputs& in, const StoredStrands& s);
  Device::Impl& dev_;
  std::map<std::string, cl::Kernel> raster_;
  std::map<int, cl::Kernel> motion_, views_;
  std::map<std::string, cl::Kernel> stored_;
  cl::Kernel export_, opacity_, store_;
};

}  // namespace clhair
