// renderer_tools.cpp — the Renderer calls that are not one frame: the reference (many
// shifted frames averaged, their hair traced by Embree or drawn by the strand pass), strand
// export of a hair mesh or strand file, the AO bake, and the device footprint and release
// of cached grooms.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <utility>

#include "frame/view_math.h"
#include "groom/strand_file_gpu.h"
#include "groom/strand_tracer.h"
#include "renderer_impl.h"

namespace clhair {

const char* referenceMethodName(ReferenceMethod m) {
  return m == ReferenceMethod::Embree ? "embree" : "raster";
}

ReferenceMethod parseReferenceMethod(const std::string& name) {
  if (name == "embree") return ReferenceMethod::Embree;
  if (name == "raster") return ReferenceMethod::Raster;
  throw Error("reference method \"" + name + "\" is not embree or raster");
}

namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// The centre layers of a traced reference frame: every pixel's ray is traced once the
// opaque scene's depth is known, then each groom takes the words of the hits on it.
class TracedLayers final : public GBufferSource {
 public:
  explicit TracedLayers(StrandTracer& tracer) : tracer_(tracer) {}
  void opaqueDrawn(const gpu::ClhViewGpu& view, const std::vector<float>& depth) override {
    const auto t0 = std::chrono::steady_clock::now();
    tracer_.trace(view, depth);
    traceMs += msSince(t0);
  }
  void centreLayer(std::uint32_t draw, const gpu::ClhGroomGpu& params,
                   std::vector<std::uint64_t>& words) override {
    tracer_.centreLayer(draw, params, words);
  }
  double traceMs = 0.0;  // wall time of the traces

 private:
  StrandTracer& tracer_;
};

// The strands of every groom instance the camera sees, as the strand pass draws them with
// LOD off (exported once per groom, placed per instance), in a tracer. Wall times of the
// exports and of building the curves and their BVH go to *exportMs and *buildMs.
std::unique_ptr<StrandTracer> traceScene(Renderer::Impl& r, const Scene& s, const RenderOptions& o,
                                         double* exportMs, double* buildMs) {
  auto tracer = std::make_unique<StrandTracer>();
  r.grooms.beginFrame();
  const std::vector<GroomDraw> draws = r.resolveGrooms(s);
  ViewPass pass;
  pass.worldToView = worldToView(s.camera);
  pass.lod = o.lod;
  pass.trueWidth = o.trueWidth;
  std::map<const GroomGpu*, StrandSet> exported;
  for (std::size_t k = 0; k < draws.size(); ++k) {
    const GroomDraw& d = draws[k];
    d.groom->useAo(o.ambientOcclusion != 0);  // the exported AO is what the frame draws
    if (!d.groom->prepare(*d.state, d.instance->transform, pass)) continue;
    auto it = exported.find(d.groom);
    auto t0 = std::chrono::steady_clock::now();
    if (it == exported.end()) it = exported.emplace(d.groom, d.groom->exportStrands(1.0f)).first;
    *exportMs += msSince(t0);
    t0 = std::chrono::steady_clock::now();
    tracer->addGroom(static_cast<std::uint32_t>(k), it->second, d.state->params);
    *buildMs += msSince(t0);
  }
  const auto t0 = std::chrono::steady_clock::now();
  tracer->commit();
  *buildMs += msSince(t0);
  return tracer;
}

}  // namespace

Frame Renderer::renderReference(const Scene& s, int spp, ReferenceMethod method) {
  ReferenceOptions ro;
  ro.spp = spp;
  ro.method = method;
  return renderReference(s, ro);
}

Frame Renderer::renderReference(const Scene& s, const ReferenceOptions& ro) {
  const int spp = ro.spp;
  if (spp < 1 || spp > 65536)
    throw Error("reference: --spp " + std::to_string(spp) + " is outside 1..65536");
  RenderOptions o;
  o.lod = 0;
  o.msaa = 1;
  o.filter = 0;
  o.trueWidth = true;   // no minimum hit diameter
  o.raster = 0;         // point samples of the strands, whatever the scene's raster
  o.segmentBudget = 0;  // every strand of every groom
  std::unique_ptr<StrandTracer> tracer;
  std::unique_ptr<TracedLayers> layers;
  double exportMs = 0.0, buildMs = 0.0;
  if (ro.method == ReferenceMethod::Embree) {
    tracer = traceScene(*impl_, s, o, &exportMs, &buildMs);
    layers = std::make_unique<TracedLayers>(*tracer);
  }
  Frame sum;
  std::vector<double> acc;
  for (int i = 0; i < spp; ++i) {
    // R2 sequence (Roberts 2018) around the pixel center, first sample at the center
    const double g = 1.32471795724474602596;
    o.jitterX = static_cast<float>(std::fmod(0.5 + i / g, 1.0) - 0.5);
    o.jitterY = static_cast<float>(std::fmod(0.5 + i / (g * g), 1.0) - 0.5);
    Frame f = layers ? impl_->frame(s, o, layers.get()) : render(s, o);
    if (i == 0) {
      sum = f;
      acc.assign(f.color.rgba.begin(), f.color.rgba.end());
    } else {
      for (std::size_t k = 0; k < acc.size(); ++k) acc[k] += f.color.rgba[k];
      for (std::size_t k = 0; k < sum.depth.size(); ++k)
        sum.depth[k] = std::min(sum.depth[k], f.depth[k]);
      for (std::size_t k = 0; k < sum.timings.size() && k < f.timings.size(); ++k)
        sum.timings[k].ms += f.timings[k].ms;
    }
    if (ro.progress) ro.progress(i + 1, spp);
  }
  for (std::size_t k = 0; k < acc.size(); ++k) sum.color.rgba[k] = static_cast<float>(acc[k] / spp);
  if (layers) {  // wall times of the traced reference's host work
    for (auto [stage, ms] : {std::pair<const char*, double>{"export", exportMs},
                             {"bvh", buildMs},
                             {"trace", layers->traceMs}}) {
      StageTime t;
      t.stage = stage;
      t.ms = ms;
      sum.timings.push_back(t);
    }
  }
  return sum;
}

StrandSet Renderer::generateStrands(const HairMesh& mesh, float lod) {
  validateHairMesh(mesh, mesh.name);
  if (!(lod > 0.0f && lod <= 1.0f))
    throw Error("strand export: LOD value " + std::to_string(lod) + " is outside (0, 1]");
  // the caller's mesh, borrowed for this call
  HairMeshGpu g(std::shared_ptr<const HairMesh>(&mesh, [](const HairMesh*) {}), impl_->stages,
                false);
  return g.exportStrands(lod);
}

StrandSet Renderer::generateStrands(const StrandGroom& groom, float lod) {
  if (!(lod > 0.0f && lod <= 1.0f))
    throw Error("strand export: LOD value " + std::to_string(lod) + " is outside (0, 1]");
  StrandFileGpu g(std::shared_ptr<const StrandGroom>(&groom, [](const StrandGroom*) {}),
                  impl_->stages);
  return g.exportStrands(lod);
}

std::uint64_t Renderer::groomDeviceBytes(const GroomInstance& groom) {
  return impl_->grooms.get(groom).deviceBytes();
}

std::vector<float> Renderer::bakeAmbientOcclusion(const HairMesh& mesh) {
  validateHairMesh(mesh, mesh.name);
  return HairMeshGpu::bakeAo(mesh, impl_->stages);
}

void Renderer::releaseGrooms() { impl_->grooms.releaseUnused(); }

}  // namespace clhair
