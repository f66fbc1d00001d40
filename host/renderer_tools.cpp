// renderer_tools.cpp — the Renderer calls that are not one frame: the reference (many
// shifted frames averaged, their hair traced by Embree or drawn by the strand pass), strand
// export of a hair mesh or strand file, the AO bake, and the device footprint and release
// of cached grooms.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <utility>

#include "groom/strand_file_gpu.h"
#include "groom/strand_tracer.h"
#include "renderer_impl.h"
#include "stages/view_math.h"

namespace clhair {

const char* referenceMethodName(ReferenceMethod m) {
  return m == ReferenceMethod::Embree ? "embree" : m == ReferenceMethod::Path ? "path" : "raster";
}

ReferenceMethod parseReferenceMethod(const std::string& name) {
  if (name == "embree") return ReferenceMethod::Embree;
  if (name == "raster") return ReferenceMethod::Raster;
  if (name == "path") return ReferenceMethod::Path;
  throw Error("reference method \"" + name + "\" is not embree, raster or path");
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

// The opaque scene in the camera's view space, for the path reference: spheres, planes (a
// square 200 units wide about the camera's foot on the plane, two triangles) and meshes.
void addOpaqueScene(StrandTracer& tracer, const Scene& s) {
  const glm::mat4 w2v = worldToView(s.camera);
  auto toView = [&](const glm::vec3& p) { return glm::vec3(w2v * glm::vec4(p, 1.0f)); };
  for (const Sphere& sp : s.spheres) {
    const glm::vec3 c = toView(sp.center);
    const float centre[3] = {c.x, c.y, c.z}, albedo[3] = {sp.color.x, sp.color.y, sp.color.z};
    tracer.addSphere(centre, sp.radius, albedo);
  }
  for (const Plane& pl : s.planes) {
    const float len = glm::length(pl.normal);
    if (!(len > 0.0f)) continue;
    const glm::vec3 n = pl.normal / len;
    const glm::vec3 foot =
        s.camera.position - (glm::dot(n, s.camera.position) - pl.offset / len) * n;
    const glm::vec3 a = glm::normalize(std::fabs(n.x) < 0.9f ? glm::cross(n, glm::vec3(1, 0, 0))
                                                             : glm::cross(n, glm::vec3(0, 1, 0)));
    const glm::vec3 b = glm::cross(n, a);
    std::vector<float> pos;
    for (const glm::vec2 c :
         {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
      const glm::vec3 p = toView(foot + 100.0f * (c.x * a + c.y * b));
      pos.insert(pos.end(), {p.x, p.y, p.z});
    }
    const float albedo[3] = {pl.color.x, pl.color.y, pl.color.z};
    tracer.addTriangles(pos, {0, 1, 2, 0, 2, 3}, albedo);
  }
  for (const MeshInstance& mi : s.meshes) {
    if (!mi.mesh) continue;
    std::vector<float> pos;
    pos.reserve(3 * mi.mesh->positions.size());
    for (const glm::vec3& q : mi.mesh->positions) {
      const glm::vec3 p = toView(glm::vec3(mi.transform * glm::vec4(q, 1.0f)));
      pos.insert(pos.end(), {p.x, p.y, p.z});
    }
    const float albedo[3] = {mi.color.x, mi.color.y, mi.color.z};
    tracer.addTriangles(pos, mi.mesh->indices, albedo);
  }
}

// The strands of every groom instance the camera sees, as the strand pass draws them with
// LOD off (exported once per groom, placed per instance), in a tracer. Wall times of the
// exports and of building the curves and their BVH go to *exportMs and *buildMs.
std::unique_ptr<StrandTracer> traceScene(Renderer::Impl& r, const Scene& s, const RenderOptions& o,
                                         double* exportMs, double* buildMs, bool pathMode = false) {
  auto tracer = std::make_unique<StrandTracer>(pathMode);
  r.grooms.beginFrame();
  const std::vector<GroomDraw> draws = r.resolveGrooms(s);
  ViewDraw pass;
  pass.worldToView = worldToView(s.camera);
  pass.lod = o.lod;
  pass.trueWidth = o.trueWidth;
  std::map<const GroomGpu*, StrandSet> exported;
  for (std::size_t k = 0; k < draws.size(); ++k) {
    const GroomDraw& d = draws[k];
    d.groom->useAo(o.ambientOcclusion);  // the exported AO is what the frame draws
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
  if (pathMode) addOpaqueScene(*tracer, s);
  tracer->commit();
  *buildMs += msSince(t0);
  return tracer;
}

// The path reference (ReferenceMethod::Path): grooms as traceScene places them, the opaque
// scene beside them, every pixel's paths traced on the CPU.
Frame pathReference(Renderer::Impl& r, const Scene& s, const RenderOptions& o,
                    const ReferenceOptions& ro) {
  if (s.environment.enabled)
    throw Error(
        "reference path: environment lighting is not simulated (the path reference lights "
        "with the scene's lights and constant ambient); render it with --reference embree");
  if (!s.backgroundImage.empty())
    throw Error("reference path: a background image is not simulated; remove \"" +
                s.backgroundImage + "\" or render with --reference embree");
  if (ro.pathEvents < 1 || ro.pathEvents > 1024)
    throw Error("reference path: " + std::to_string(ro.pathEvents) +
                " scattering events per path is outside 1..1024");
  double exportMs = 0.0, buildMs = 0.0;
  std::unique_ptr<StrandTracer> tracer = traceScene(r, s, o, &exportMs, &buildMs, true);
  StrandTracer::PathSetup ps;
  ps.view = makeView(s.camera, s.width, s.height);
  const glm::mat4 w2v = worldToView(s.camera);
  for (const Light& l : s.lights) {
    StrandTracer::PathLight pl;
    pl.point = l.type == Light::Type::Point;
    const glm::vec3 p = pl.point ? glm::vec3(w2v * glm::vec4(l.position, 1.0f))
                                 : glm::normalize(glm::vec3(w2v * glm::vec4(l.direction, 0.0f)));
    const glm::vec3 c = l.color * l.intensity;
    for (int k = 0; k < 3; ++k) {
      pl.pos[k] = p[k];
      pl.rgb[k] = c[k];
    }
    ps.lights.push_back(pl);
  }
  for (int k = 0; k < 3; ++k) {
    ps.ambient[k] = s.ambient[k];
    ps.background[k] = s.background[k];
  }
  ps.spp = ro.spp;
  ps.maxEvents = ro.pathEvents;
  ps.seed = ro.pathSeed;
  const auto t0 = std::chrono::steady_clock::now();
  StrandTracer::PathImage img = tracer->tracePaths(ps);
  const double traceMs = msSince(t0);
  if (ro.progress) ro.progress(ro.spp, ro.spp);
  Frame f;
  f.color.width = s.width;
  f.color.height = s.height;
  f.color.rgba.resize(4 * img.depth.size());
  for (std::size_t i = 0; i < img.depth.size(); ++i) {
    for (int c = 0; c < 3; ++c) f.color.rgba[4 * i + c] = img.rgb[3 * i + c];
    f.color.rgba[4 * i + 3] = 1.0f;
  }
  f.depth = std::move(img.depth);
  f.stats.pathRays = img.rays;
  f.stats.pathEscapedAfter = std::move(img.escapedAfter);
  for (double& e : f.stats.pathEscapedAfter) e /= static_cast<double>(f.depth.size());
  for (auto [stage, ms] :
       {std::pair<const char*, double>{"export", exportMs}, {"bvh", buildMs}, {"paths", traceMs}}) {
    StageTime t;
    t.stage = stage;
    t.ms = ms;
    f.timings.push_back(t);
  }
  return f;
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
  // one sample per pixel per pass, shaded per sample, whatever the scene says
  o.quality = Quality::Draft;
  o.pointShading = Toggle::Off;
  o.lod = Toggle::Off;
  o.msaa = 1;
  o.filter = Toggle::Off;
  o.trueWidth = true;             // no minimum hit diameter
  o.raster = RasterMode::Lines;   // point samples of the strands, whatever the scene's raster
  o.segmentBudget = 0;            // every strand of every groom
  o.shadowResFromCamera = false;  // maps at the scene's resolution, whatever the camera sees
  if (ro.method == ReferenceMethod::Path) return pathReference(*impl_, s, o, ro);
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
    Frame f = layers ? wait(impl_->enqueue(impl_->submitFrame(s, {s.camera}, o, layers.get())))
                     : render(s, o);
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
