// renderer.cpp — the frame loop. Per frame: the target and the scene on the device are
// brought up to date, the grooms are resolved to their device forms and instance slots,
// the deep opacity maps are rebuilt if their inputs changed, the opaque scene is drawn,
// and then every groom in turn runs lod -> scan + sizing -> strands -> shade -> filter ->
// composite over the same target. The pieces (host/frame/, host/groom/, host/stages/)
// each own one job; this file only orders them and reads the frame back.
#include "clhair/renderer.h"

#include <cmath>
#include <map>

#include "cl/buffers.h"
#include "cl/device_impl.h"
#include "frame/render_target.h"
#include "frame/scene_gpu.h"
#include "frame/shadow_pass.h"
#include "frame/view_math.h"
#include "groom/groom_cache.h"
#include "groom/hair_mesh_gpu.h"
#include "groom/strand_file_gpu.h"
#include "stages/ao_stage.h"
#include "stages/composite_stage.h"
#include "stages/filter_stage.h"
#include "stages/shade_stage.h"

namespace clhair {

struct Renderer::Impl {
  Device device;
  Device::Impl& dev;
  LodStage lod;
  StrandStage strands;
  ExplicitStage explicitStrands;
  AoStage ao;
  RootSetsGpu roots;
  GroomStages stages;
  GroomCache grooms;
  ShadeStage shade;
  FilterStage filter;
  CompositeStage composite;
  RenderTarget target;
  SceneGpu scene;
  ShadowPass shadows;
  Profiler profiler;

  explicit Impl(Device d)
      : device(std::move(d)),
        dev(*device.impl()),
        lod(dev),
        strands(dev),
        explicitStrands(dev),
        ao(dev),
        stages{dev, lod, strands, explicitStrands, ao, roots},
        grooms(stages),
        shade(dev),
        filter(dev),
        composite(dev),
        target(dev),
        scene(dev),
        shadows(dev) {}

  // CPU devices: the benchmark's dispatch section (bench/README.md) measured read-back and
  // over-launch level within noise on PoCL, persistent no better, and read-back launches
  // exactly the drawn strands, so it is the CPU default. GPUs: over-launch avoids the host
  // round trip between the pre-pass and the strand pass (a pipeline bubble per groom on a
  // discrete GPU), and surplus work-groups leave after one load. Re-run
  // `clhair_bench --only dispatch` on a GPU and change this if it disagrees.
  DispatchMode resolveMode(DispatchMode m) const {
    if (m != DispatchMode::Auto) return m;
    return dev.info.isGpu ? DispatchMode::OverLaunch : DispatchMode::ReadBack;
  }

  // Every groom instance of the scene with its device form; the k-th instance of one
  // groom gets instance slot k.
  std::vector<GroomDraw> resolveGrooms(const Scene& s) {
    std::vector<GroomDraw> draws;
    std::map<const GroomGpu*, std::size_t> seen;
    for (const GroomInstance& gi : s.grooms) {
      GroomGpu& g = grooms.get(gi);
      draws.push_back({&gi, &g, &g.instance(seen[&g]++)});
    }
    return draws;
  }
};

Renderer::Renderer(Device device) : impl_(std::make_unique<Impl>(std::move(device))) {}
Renderer::~Renderer() = default;

const Device& Renderer::device() const { return impl_->device; }

Frame Renderer::render(const Scene& s, const RenderOptions& options) {
  Impl& r = *impl_;
  RenderTarget& t = r.target;
  t.ensure(s.width, s.height, options.msaa);
  r.scene.upload(s);
  gpu::ClhViewGpu view = makeView(s.camera, s.width, s.height);
  view.samples = static_cast<gpu::clh_u32>(options.msaa);
  view.cx += options.jitterX;
  view.cy += options.jitterY;
  upload(r.dev, t.view, &view, 1);
  const std::size_t pixels = t.pixels();
  const DispatchMode mode = r.resolveMode(options.dispatch);
  Frame frame;
  r.profiler.hostTiming = options.stageCores;
  if (options.rasterStats) {
    const cl_uint zero[4] = {0, 0, 0, 0};
    upload(r.dev, t.stats, zero, 4);
  }
  r.grooms.beginFrame();
  std::vector<GroomDraw> draws = r.resolveGrooms(s);

  const bool lodCorrection =
      options.shadowLodCorrection < 0 ? s.shadows.lodCorrection : options.shadowLodCorrection == 1;
  r.shadows.update(s, options, lodCorrection, draws, r.scene, &r.profiler);
  const ShadowMapInputs maps = r.shadows.maps();
  r.scene.drawOpaque(t.viewTarget(), maps, t.color, t.depth, true, &r.profiler);

  ViewPass pass;
  pass.view = &t.view;
  pass.worldToView = worldToView(s.camera);
  pass.lod = options.lod;
  pass.lodLambdaScale = options.lodLambdaScale;
  pass.trueWidth = options.trueWidth;
  pass.shadowLodCorrection = lodCorrection;
  StrandRaster raster;
  raster.view = &t.view;
  raster.sceneDepth = &t.depth;
  raster.gbuffer = &t.gbuffer;
  raster.counters = &t.stats;
  raster.pixels = pixels;
  raster.msaa = options.msaa;
  raster.stats = options.rasterStats;
  raster.mode = mode;
  std::vector<const GroomDraw*> drawn;
  for (const GroomDraw& d : draws) {
    GroomInstanceGpu& inst = *d.state;
    d.groom->useAo(options.ambientOcclusion != 0);
    if (!d.groom->prepare(inst, d.instance->transform, pass)) continue;
    drawn.push_back(&d);
    d.groom->lod(inst, t.view, &r.profiler);
    raster.strands = mode == DispatchMode::ReadBack ? d.groom->readTotal(inst) : d.groom->strandCount();
    t.clearGBuffer(&r.profiler);
    d.groom->raster(inst, raster, &r.profiler);
    if (options.captureGBuffer) {  // the raster's inputs, before compositing changes the depth
      const auto* gb = reinterpret_cast<const std::uint8_t*>(&inst.params);
      const auto* vb = reinterpret_cast<const std::uint8_t*>(&view);
      frame.rasterGroom.assign(gb, gb + sizeof(gpu::ClhGroomGpu));
      frame.rasterView.assign(vb, vb + sizeof(gpu::ClhViewGpu));
      frame.rasterDepth.resize(pixels);
      readBack(r.dev, "the depth the hair was tested against", t.depth, frame.rasterDepth.data(), pixels);
    }
    if (options.rasterOnly) continue;
    ShadeStage::Params sp;
    sp.target = t.viewTarget();
    sp.lighting = r.scene.lighting(maps);
    sp.groom = &inst.groom;
    sp.offsets = &inst.offsets;
    sp.totalIndex = inst.records;
    sp.gbuffer = &t.gbuffer;
    sp.hair = &t.hair;
    sp.msaa = options.msaa;
    r.shade.enqueue(sp, &r.profiler);
    const FilterParams& fp = d.instance->hasFilter ? d.instance->filter : s.filter;
    const bool filtered = options.msaa == 1 && (options.filter < 0 ? fp.enabled : options.filter == 1);
    if (filtered) r.filter.enqueue(fp, {t.viewTarget(), &inst.groom, &t.gbuffer, &t.hair, &t.filtered}, &r.profiler);
    r.composite.enqueue({t.viewTarget(), &inst.groom, filtered ? &t.filtered : &t.hair, &t.gbuffer, &t.color, &t.depth,
                         options.msaa, filtered ? 2 : options.msaa},
                        &r.profiler);
  }

  frame.color.width = s.width;
  frame.color.height = s.height;
  frame.color.rgba.resize(pixels * 4);
  frame.depth.resize(pixels);
  readBack(r.dev, "the frame", t.color, frame.color.rgba.data(), pixels * 4);
  readBack(r.dev, "the frame's depth", t.depth, frame.depth.data(), pixels);
  for (const GroomDraw* d : drawn) frame.stats.strandsDrawn += d->groom->readTotal(*d->state);
  frame.stats.shadowStrandsDrawn = r.shadows.strandsDrawn();
  if (options.captureGBuffer) {
    frame.gbufferLayers = t.layers();
    frame.gbuffer.assign(pixels * t.layers(), ~std::uint64_t(0));
    if (!drawn.empty()) readBack(r.dev, "the G-buffer", t.gbuffer, frame.gbuffer.data(), frame.gbuffer.size());
  }
  if (options.rasterStats) {
    cl_uint st[4];
    readBack(r.dev, "raster statistics", t.stats, st, 4);
    frame.stats.pixelWrites = st[0];
    frame.stats.atomicsIssued = st[1];
    frame.stats.atomicsSkipped = st[2];
    frame.stats.segmentsDrawn = st[3];
  }
  frame.timings = r.profiler.collect();
  r.grooms.trim();
  return frame;
}

Frame Renderer::renderReference(const Scene& s, int spp) {
  if (spp < 1 || spp > 65536) throw Error("reference: --spp " + std::to_string(spp) + " is outside 1..65536");
  RenderOptions o;
  o.lod = 0;
  o.msaa = 1;
  o.filter = 0;
  o.trueWidth = true;  // no minimum hit diameter
  Frame sum;
  std::vector<double> acc;
  for (int i = 0; i < spp; ++i) {
    // R2 sequence (Roberts 2018) around the pixel center, first sample at the center
    const double g = 1.32471795724474602596;
    o.jitterX = static_cast<float>(std::fmod(0.5 + i / g, 1.0) - 0.5);
    o.jitterY = static_cast<float>(std::fmod(0.5 + i / (g * g), 1.0) - 0.5);
    Frame f = render(s, o);
    if (i == 0) {
      sum = f;
      acc.assign(f.color.rgba.begin(), f.color.rgba.end());
    } else {
      for (std::size_t k = 0; k < acc.size(); ++k) acc[k] += f.color.rgba[k];
      for (std::size_t k = 0; k < sum.depth.size(); ++k) sum.depth[k] = std::min(sum.depth[k], f.depth[k]);
      for (std::size_t k = 0; k < sum.timings.size() && k < f.timings.size(); ++k) sum.timings[k].ms += f.timings[k].ms;
    }
  }
  for (std::size_t k = 0; k < acc.size(); ++k) sum.color.rgba[k] = static_cast<float>(acc[k] / spp);
  return sum;
}

StrandSet Renderer::generateStrands(const HairMesh& mesh, float lod) {
  validateHairMesh(mesh, mesh.name);
  if (!(lod > 0.0f && lod <= 1.0f)) throw Error("strand export: LOD value " + std::to_string(lod) + " is outside (0, 1]");
  // the caller's mesh, borrowed for this call
  HairMeshGpu g(std::shared_ptr<const HairMesh>(&mesh, [](const HairMesh*) {}), impl_->stages, false);
  return g.exportStrands(lod);
}

StrandSet Renderer::generateStrands(const StrandGroom& groom, float lod) {
  if (!(lod > 0.0f && lod <= 1.0f)) throw Error("strand export: LOD value " + std::to_string(lod) + " is outside (0, 1]");
  StrandFileGpu g(std::shared_ptr<const StrandGroom>(&groom, [](const StrandGroom*) {}), impl_->stages);
  return g.exportStrands(lod);
}

std::uint64_t Renderer::groomDeviceBytes(const GroomInstance& groom) { return impl_->grooms.get(groom).deviceBytes(); }

std::vector<float> Renderer::bakeAmbientOcclusion(const HairMesh& mesh) {
  validateHairMesh(mesh, mesh.name);
  return HairMeshGpu::bakeAo(mesh, impl_->stages);
}

void Renderer::releaseGrooms() { impl_->grooms.releaseUnused(); }

}  // namespace clhair
