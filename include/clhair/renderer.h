// renderer.h — the public entry point: render a Scene on a Device into a Frame.
//
// A Renderer owns the programs, the per-groom device resources (uploaded once per hair mesh
// or StrandGroom) and the buffers sized to the render target. render() runs, for every groom in
// turn, lod -> scan + sizing -> strands -> shade -> composite over the opaque scene, and returns
// colour, alpha, depth and per-stage times taken from OpenCL profiling events.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "clhair/cryptomatte.h"
#include "clhair/device.h"
#include "clhair/frame_types.h"
#include "clhair/image.h"
#include "clhair/labels.h"
#include "clhair/scene.h"

namespace clhair {

struct RenderOptions {
  Toggle lod = Toggle::Default;  // Default: as each groom says
  float lodLambdaScale = 1.0f;
  int msaa = 1;  // samples per pixel: 1, 2, 4 or 8 (software MSAA, averaged)
  // Shading once per visible strand point (DESIGN.md): the points whose segments own a
  // visible sample are shaded once each and every sample takes the colour interpolated
  // along its segment; Default as the quality level says (kGoodPointShading for good and
  // final's good passes, else off), Off: every sample shaded. No filter runs on such a frame;
  // frames of several views, the coverage raster and references shade every sample.
  Toggle pointShading = Toggle::Default;
  // The quality level (clhair/scene.h, Quality; README "Quality"), nullopt: as the scene says.
  // Draft: the options as given; Good: msaa kGoodMsaa unless more than 1 is given,
  // kGoodPointShading, no filter; Final: render() accumulates jittered passes
  // (ProgressiveStill in clhair/progressive.h; submit() refuses it).
  std::optional<Quality> quality;
  int spp = 0;  // final: jittered passes, 0 as the scene says (kDefaultFinalPasses by default)
  // final's passes (FinalPath): the measured default, one sample per pixel without a filter,
  // or the good path
  FinalPath finalPath = FinalPath::Default;
  Toggle filter = Toggle::Default;  // reconstruction filter with MSAA 1; Default: as the scene says
  // Which filter, nullopt: as the scene says (FilterParams::method). Lipp; Huang (linking,
  // alpha fix, anisotropic filter); Auto, here as in the scene (its default): Huang's in one
  // view and Lipp's in several.
  std::optional<FilterParams::Method> filterMethod;
  // The strand raster (Scene::raster), nullopt: as the scene says. Coverage: MSAA 1, one view;
  // no filter, strand identities, or motion layer of deforming grooms.
  std::optional<RasterMode> raster;
  // LOD in the lights' passes; Default: on unless lod is Off
  Toggle shadowLod = Toggle::Default;
  // Lipp §3.2.3 depth shift; Default: as the scene says (ShadowParams::lodCorrection)
  Toggle shadowLodCorrection = Toggle::Default;
  // The lights' passes draw no more strands and control points per bundle than the camera's
  // LOD does for a groom the camera draws with LOD (DESIGN.md, "Light-pass LOD from the
  // camera") unless Off (the light's view alone). It acts where the lights' passes draw
  // with LOD (shadowLod).
  Toggle shadowLodCamera = Toggle::Default;
  // The deep opacity maps' resolution follows the camera's view of the grooms (a texel per
  // pixel of their bounding sphere on screen, to a power of two, at most the scene's
  // ShadowParams::resolution: ShadowPass::mapResolution); false: the scene's resolution.
  // Frames of several views use the scene's.
  bool shadowResFromCamera = true;
  DispatchMode dispatch = DispatchMode::Auto;
  bool rasterStats = false;  // count pixel writes and atomics (slower; benchmark)
  float jitterX = 0.0f;      // sub-pixel shift of the image plane, pixels (reference passes, tests)
  float jitterY = 0.0f;
  bool captureGBuffer = false;  // keep the last groom's G-buffer layers in Frame::gbuffer
  bool rasterOnly = false;      // stop each groom after its strand pass (benchmark: cores used)
  bool stageCores = false;  // wait for every dispatch and time it on the host (StageTime::cpuMs)
  // true: each groom's G-buffer clear, hair linking, Huang's filter and compositing after it
  // run over the groom's screen box (its bounds projected, DESIGN.md "Screen boxes"); false:
  // over the whole frame, as before them. The frame is bit-identical either way (tests).
  bool screenBoxes = true;
  // Keep the deep opacity maps of the previous frame when nothing they depend on changed
  // (lights, shadow settings, grooms and their transforms, opaque objects, LOD options; the
  // camera enters only through the grooms' size on its screen, to half an octave, and the
  // maps' resolution: not the jitter of final's passes). false: rebuild them every frame.
  bool reuseShadows = true;
  // A still of quality final (ProgressiveStill) assembles each hair mesh's strands once, in
  // its first pass, and draws them from there in every pass where the device's memory allows
  // (LOD chosen once per still; the jitter never changes it for a groom inside the frame).
  // false: every pass assembles its strands again.
  bool reuseAssembly = true;
  // The still this frame is a pass of, and the pass's index in it, set by ProgressiveStill
  // (still 0: a frame of its own).
  std::uint64_t still = 0;
  int stillPass = 0;
  // Quality final with reuseAssembly: each pass draws one hair-mesh strand in N (a different
  // subset per pass, every strand once in N passes in a row), widened N-fold to keep the
  // hair's coverage; 1 (default) draws every strand in every pass. 1..16.
  int finalSubset = 1;
  bool ambientOcclusion = true;  // baked AO (baked on first use when the mesh has none)
  // true: grooms with a baked visibility (GroomInstance::visibility) use it for the lights
  // without a deep opacity map; false: ignore it (the frame is then bit-identical to one
  // without)
  bool bakedVisibility = true;
  // true: strands LOD widened to stand for a cluster are shaded with the aggregated BCSDF
  // (Huang et al. 2024); false (default): with the single-fibre BSDF like full-detail
  // strands. Off by default: against the traced full-groom reference it raises the LOD
  // frame's FLIP (docs/hair-shading.md §6, `clhair_bench --only quality`).
  bool lodAggregate = false;
  // true (default): hair is lit with the light scattered between fibres too (dual
  // scattering, Zinke et al. 2008: kernels/common/hair_dual.h) for the lights with a deep
  // opacity map and the probe light; false: every fibre scatters the light that reaches it
  // once (docs/hair-shading.md §8).
  bool multipleScattering = true;
  // Every strand at its true projected width: the grooms' minimum hit diameter is ignored
  // and a faint strand file is not widened (the passes of renderReference).
  bool trueWidth = false;
  // Fill Frame::aovs (clhair/aov.h): depth, hair alpha, tangent and motion per pixel. Costs
  // a read-back of each groom's centre G-buffer layers and shaded hair.
  bool aovs = false;
  // Segment budget (Scene::segmentBudget): -1 as the scene says, 0 none, > 0 at most this
  // many segments per frame over all grooms drawn with LOD.
  std::int64_t segmentBudget = -1;
  // How the segment budget shares the segments out (BudgetRule; Default: the screen rule)
  BudgetRule budgetRule = BudgetRule::Default;
  // The screen rule's claim: a groom whose screen box covers more than budgetKeepHigh of
  // the image keeps its LOD count while the other grooms' cuts down to their floors pay for
  // it; the claim ramps in from budgetKeepLow (smoothstep; equal values: a hard threshold).
  float budgetKeepLow = 0.15f, budgetKeepHigh = 0.25f;
  // Under the screen rule, the most the budget widens a surviving strand on top of LOD's
  // own widening (>= 1; 0: no cap, the survivors stand for every strand removed). Kept for
  // measurement: widening in full measured best (DESIGN.md "The segment budget").
  float budgetWidenCap = 0.0f;
  // The strand pass also writes the identity layer next to the centre layer (MSAA 1 only;
  // gpu_types.h), and with aovs the frame gets the strand layer (clhair/aov.h). Huang's
  // filter writes it whatever this says.
  bool strandIds = false;
  // With aovs: Frame::cryptomatte gets the ID mattes per groom and per strand
  // (clhair/cryptomatte.h). Needs MSAA 1 and the lines raster (it reads strand identities, as
  // strandIds does).
  bool cryptomatte = false;
  // With aovs: the still scene of the previous frame (sceneAtFrame(scene, frame - 1)), whose
  // camera, groom transforms and cages or per-frame strands (grooms matched by index) give the
  // motion layer; null: the motion is zero.
  const Scene* previous = nullptr;
  // Per-stage device times in Frame::timings (profiling events). false: no event is asked
  // for, and the frame costs nothing to time (sequences that print no stage times).
  bool timings = true;
  // Frame::depth is read back (false: it stays empty unless aovs need it; a frame written as
  // an image needs only its colour, and a discrete GPU then sends a fifth fewer bytes).
  bool readBackDepth = true;
  // Frame::passes gets the frame's graph as text (clhair render --passes).
  bool describePasses = false;
  // Temporal reprojection (TemporalParams in clhair/scene.h): frames of history, -1 as the
  // scene's "temporal" says, 0 off, 1..kMaxTemporalHistory. Read by FrameSequence
  // (clhair/temporal.h), which renders the frames before; render() draws the still alone.
  int temporal = -1;
};

// How Renderer::renderReference finds what each sample sees.
enum class ReferenceMethod {
  // The strands traced as round curves with Embree (the independent ground truth): the
  // nearest fibre along the sample's ray, at its true width, shaded from the G-buffer word
  // the strand pass would write there.
  Embree,
  // The strand pass itself (one centre sample per pixel, true width) on a shifted image
  // plane: shares any coverage error of the rasterizer.
  Raster,
  // A CPU path tracer through the Embree curves and the opaque scene (spheres, planes,
  // meshes as Lambertian surfaces): light scattered between fibres any number of times, each
  // event with the shading pass's single-fibre BSDF; every light shadowed by the real
  // geometry (no deep opacity maps, no baked visibility or AO); the constant ambient as a
  // uniform environment. docs/path-reference.md.
  Path,
};
const char* referenceMethodName(ReferenceMethod m);
// "embree", "raster" or "path"
ReferenceMethod parseReferenceMethod(const std::string& name);

struct ReferenceOptions {
  int spp = 256;  // samples per pixel, 1..65536
  ReferenceMethod method = ReferenceMethod::Embree;
  // Called after every sample pass with the passes done and their total.
  std::function<void(int done, int total)> progress;
  // Path only: scattering events per path (1: the light at the first fibre or surface seen,
  // shadowed; no interreflection, no ambient) and the seed of its random numbers.
  int pathEvents = 64;
  std::uint32_t pathSeed = 1;
};

// What one groom instance drew in the camera pass, from its LOD records as the strand
// pass read them (after the segment budget).
struct GroomDrawStats {
  std::size_t instance = 0;          // index in Scene::grooms
  std::string name;                  // GroomInstance::name
  bool drawn = false;                // false: entirely behind the camera (nothing below is set)
  std::uint32_t strands = 0;         // strands drawn
  std::uint64_t segments = 0;        // segments drawn (strand files under the budget: see docs)
  std::uint32_t visibleStrands = 0;  // full-detail strands of the bundles not culled
  bool lod = false;                  // drawn with LOD (so under the segment budget)
  bool halved = false;               // every other control point dropped by the segment budget
  // What the segment budget measured and decided (DESIGN.md "The segment budget"):
  std::uint32_t requested = 0;  // segments its LOD records asked (at every other point if halved)
  std::uint32_t floor = 0;      // segments at one strand per drawn bundle (or chunk)
  std::uint32_t share = 0;      // the screen rule's share over the budget, else requested
  float screenArea = 0.0f;      // its screen box clipped to the image, pixels
  float keepClaim = 0.0f;       // its claim to keep its LOD count as it held, 0..1 (screen
                                // rule: p_d faded by the room the others leave, DESIGN.md)
};

struct FrameStats {
  std::uint64_t strandsDrawn = 0;
  // Segments the strand passes draw, from the LOD records (after the segment budget), and
  // the total of the LOD pre-passes before it.
  std::uint64_t segmentsPlanned = 0;
  std::uint64_t segmentsBeforeBudget = 0;
  std::uint64_t segmentBudget = 0;       // the budget this frame used (0: none)
  bool overBudget = false;               // the pre-passes exceeded it and strands were reduced
  float budgetScale = 1.0f;              // the uniform rule's factor on every bundle's strands
  bool budgetScreenRule = false;         // the budget shared by screen area (else uniform)
  float budgetLevel = 0.0f;              // screen rule: segments per pixel of screen box, mu
  std::vector<GroomDrawStats> grooms;    // one per groom instance of the scene, in order
  std::uint64_t shadowStrandsDrawn = 0;  // strands drawn into the deep opacity maps, all lights
  // Deep opacity maps built for this frame (one per shadowed light; 0: the previous frame's
  // were kept, RenderOptions::reuseShadows). A still of quality final sums its passes'.
  std::uint32_t shadowMapsBuilt = 0;
  int shadowResolution = 0;  // texels per side of the maps the frame read
  // points shaded once each (RenderOptions::pointShading), summed over the grooms
  std::uint64_t pointsShaded = 0;
  // with RenderOptions::rasterStats only:
  std::uint64_t segmentsDrawn = 0;   // segments the raster walked (after near clipping)
  std::uint64_t pixelWrites = 0;     // G-buffer writes that passed coverage and depth tests
  std::uint64_t atomicsIssued = 0;   // atom_min calls
  std::uint64_t atomicsSkipped = 0;  // writes the plain load showed could not lower the word
  // hair linking (FilterParams::Method::Huang), summed over the grooms:
  std::uint64_t linkSelecting = 0;   // empty pixels that chose a source strand
  std::uint64_t linkedPixels = 0;    // pixels filled by linking
  std::uint64_t linkStrands = 0;     // strands in the alpha fix's hash table
  std::uint64_t linkTurnedAway = 0;  // pixels whose strand found the hash table full
  // Times the host waited for the device for this frame, its final read-back included
  // (Renderer::wait); a steady-state frame has exactly one.
  std::uint64_t hostWaits = 0;
  // ReferenceMethod::Path: the rays its paths traced (camera, continuation and shadow rays),
  // and per number N of scattering events, the mean radiance (over channels, pixels and
  // samples) that paths brought back from the environment after N events
  std::uint64_t pathRays = 0;
  std::vector<double> pathEscapedAfter;
};

// Layers for compositing (RenderOptions::aovs); each empty without them. Per pixel, row-major.
struct FrameAovs {
  std::vector<float> z;          // view depth of Frame::depth's surface, kAovBackgroundZ: none
  std::vector<float> hairAlpha;  // the grooms' coverage, 1 - prod(1 - a_k)
  std::vector<float> tangent;    // 3 per pixel: world unit tangent of the nearest centre word
  std::vector<float> motion;     // 2 per pixel: pixels to the previous frame, x right, y up
  // with RenderOptions::strandIds, 3 per pixel: groom index, strand index, u (-1: none)
  std::vector<float> strand;
  // 4 per pixel: the grooms' premultiplied RGBA composited over transparent black (alpha is
  // hairAlpha before clamping), and the opaque scene's colour before any hair; the frame's
  // colour is hair + (1 - hair alpha) * opaque (temporal reprojection recomposes it)
  std::vector<float> hair;
  std::vector<float> opaque;
};

struct Frame {
  Image color;               // composited linear RGBA (alpha 1)
  std::vector<float> depth;  // view-space depth, +inf where nothing
  std::vector<StageTime> timings;
  FrameStats stats;
  // With RenderOptions::captureGBuffer: the last groom's layers (msaa sample layers, then
  // the conservative layer), width * height words each.
  std::vector<std::uint64_t> gbuffer;
  int gbufferLayers = 0;
  // Also with captureGBuffer: what the last groom's strand pass read, for CPU re-runs of
  // it (host/groom/cpu_raster.h): its groom and view records (ClhGroomGpu and ClhViewGpu
  // of gpu_types.h, as bytes) and the scene depth its pixels were tested against.
  std::vector<std::uint8_t> rasterGroom, rasterView;
  std::vector<float> rasterDepth;
  FrameAovs aovs;
  // With RenderOptions::aovs and cryptomatte: the layers CryptoGroom and CryptoStrand (empty
  // when no groom was drawn).
  std::vector<CryptomatteLayer> cryptomatte;
  // With RenderOptions::describePasses: the frame's passes, buffers and host waits.
  std::string passes;

  double stageMs(const std::string& stage) const;
  double totalMs() const;
};

// A frame submitted to a Renderer and not yet waited for.
using FrameTicket = std::uint64_t;
// The most frames a Renderer keeps in flight (Renderer::setFramesInFlight).
constexpr int kMaxFramesInFlight = 8;

class Renderer {
 public:
  explicit Renderer(Device device);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // One frame: submit() then wait().
  Frame render(const Scene& scene, const RenderOptions& options = {});
  // Enqueues the frame's work and its read-back and returns without waiting for the device
  // (the host may build the next frame meanwhile). When more than framesInFlight() frames
  // would run, the oldest is waited for first. The scene and options are not used after it
  // returns.
  FrameTicket submit(const Scene& scene, const RenderOptions& options = {});
  // The frame of `ticket` (blocks until the device has finished it). Each ticket is waited
  // for once, in any order.
  Frame wait(FrameTicket ticket);
  // Frames the device may work on while the host goes on (1: one frame at a time; default 2).
  void setFramesInFlight(int frames);
  int framesInFlight() const;
  // Several views of one assembly (docs/scene-format.md, "Several views"): one frame per
  // camera, in order. Every hair-mesh strand is generated once and drawn into every view's
  // G-buffer; its level of detail and culling are those of the first camera that sees the
  // groom. One camera: exactly render() with that camera. Not with aovs, captureGBuffer or
  // rasterOnly (throws clhair::Error).
  std::vector<Frame> renderViews(const Scene& scene, const std::vector<Camera>& cameras,
                                 const RenderOptions& options = {});
  // renderViews in two halves, like submit() and wait().
  FrameTicket submitViews(const Scene& scene, const std::vector<Camera>& cameras,
                          const RenderOptions& options = {});
  std::vector<Frame> waitViews(FrameTicket ticket);

  // The reference the real-time pipeline approximates: the average of `spp` frames, each
  // shifted by the same sub-pixel offset in every pixel (an R2 low-discrepancy sequence,
  // the first at the centre), so the opaque scene drawn for that frame and the hair seen
  // there agree. In each frame a pixel shows the strand its (shifted) centre sees at the
  // strand's true width: traced by Embree (ReferenceMethod::Embree) or drawn by the strand
  // pass (Raster); MSAA 1, no filter, no LOD, shaded by the shading kernel, composited per
  // frame so alpha is correct. Timings sum all frames' stages (the Embree method adds the
  // wall times of its host work: "export" of the strands, "bvh" build, "trace").
  Frame renderReference(const Scene& scene, const ReferenceOptions& options);
  Frame renderReference(const Scene& scene, int spp,
                        ReferenceMethod method = ReferenceMethod::Embree);

  // The labels hair models learn from (clhair/labels.h), computed on the device from
  // `frame`'s tangent and hair alpha layers (render it with RenderOptions::aovs) and the
  // camera it was drawn with. Throws clhair::Error when the frame has no such layers.
  HairLabels labels(const Frame& frame, const Camera& camera);

  // Ambient occlusion of every layer vertex (layer-major, 1 = open), computed on the
  // device from the groom's own hair density and scalp (kernels/ao.cl).
  std::vector<float> bakeAmbientOcclusion(const HairMesh& mesh);

  // Runs the strand kernel in export mode for `mesh`. lod = 1: full detail; lod < 1: every
  // bundle at that LOD value L (strand count, control points and morph of lod_math.h).
  StrandSet generateStrands(const HairMesh& mesh, float lod = 1.0f);

  // Runs the explicit-strand kernel in export mode: the strands as they are drawn, in the
  // renderer's LOD order (sourceStrand maps back). lod = 1: every strand and point;
  // lod < 1: every chunk at that LOD value L (strand subset, point skipping and morph).
  StrandSet generateStrands(const StrandGroom& groom, float lod = 1.0f);

  // Bytes of the device buffers the renderer keeps for this groom (uploading it first if
  // needed): hair mesh records or strand tables, parameters, LOD records and scan. Not
  // included: the blue-noise root sets all hair-mesh grooms share (at most 1 MiB) and the
  // target-sized buffers.
  std::uint64_t groomDeviceBytes(const GroomInstance& groom);

  // Device resources of grooms the last frame did not draw are kept for later frames, the
  // least recently used released beyond a few; this releases all of them now.
  void releaseGrooms();

  const Device& device() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace clhair
