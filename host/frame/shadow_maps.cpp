// shadow_maps.cpp — see shadow_maps.h.
#include "frame/shadow_maps.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "cl/buffers.h"
#include "frame/view_math.h"

namespace clhair {

ShadowMaps::ShadowMaps(Device::Impl& dev) : dev_(dev), stage_(dev), clear_(dev) {
  lightView_ = makeBuffer<gpu::ClhViewGpu>(dev, "light view parameters", 1);
  all_ = makeBuffer<gpu::ClhShadowGpu>(dev, "shadow parameters", CLH_MAX_SHADOWS);
  for (auto& b : one_) b = makeBuffer<gpu::ClhShadowGpu>(dev, "shadow parameters", 1);
  counters_ = makeBuffer<cl_uint>(dev, "light raster counters", 4);
}

void ShadowMaps::ensureBuffers(int res) {
  allocate(res);
  res_ = res;
}

void ShadowMaps::allocate(int res) {
  if (res <= capacity_) return;  // a smaller map uses the front of the planes
  const std::size_t plane = static_cast<std::size_t>(res) * res;
  const std::string what = std::to_string(res) + "x" + std::to_string(res) + " deep opacity maps";
  opaque_ = makeBuffer<cl_float>(dev_, what, plane * CLH_MAX_SHADOWS);
  hair_ = makeBuffer<cl_float>(dev_, what, plane * CLH_MAX_SHADOWS);
  opacity_ = makeBuffer<cl_uint>(dev_, what, plane * CLH_MAX_SHADOWS * CLH_DOM_LAYERS);
  lightColor_ = makeBuffer<cl_float4>(dev_, what, plane);
  lightDepth_ = makeBuffer<cl_float>(dev_, what, plane);
  lightGBuffer_ = makeBuffer<cl_ulong>(dev_, what, plane * 2);
  capacity_ = res;
}

void ShadowMaps::reserve(const Scene& s) {
  if (s.grooms.empty()) return;
  for (const Light& l : s.lights)
    if (l.shadows) {
      allocate(s.shadows.resolution);
      return;
    }
}

std::vector<const cl::Buffer*> ShadowMaps::mapBuffers() const {
  return {&all_, &opaque_, &hair_, &opacity_};
}

std::vector<const cl::Buffer*> ShadowMaps::buffers() const {
  std::vector<const cl::Buffer*> b = mapBuffers();
  b.insert(b.end(), {&lightView_, &lightColor_, &lightDepth_, &lightGBuffer_, &counters_, &totals_,
                     &cameraLod_});
  for (const cl::Buffer& one : one_) b.push_back(&one);
  return b;
}

ShadowMapInputs ShadowMaps::maps() const {
  ShadowMapInputs m;
  m.params = &all_;
  m.opaqueDepth = &opaque_;
  m.hairDepth = &hair_;
  m.opacity = &opacity_;
  m.texels = static_cast<std::size_t>(res_) * static_cast<std::size_t>(res_);
  return m;
}

ShadowMaps::Key ShadowMaps::keyOf(const Scene& s, const RenderOptions& o, bool lodCorrection) {
  Key k;
  auto put = [&k](const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    k.bytes.insert(k.bytes.end(), b, b + n);
  };
  auto putValue = [&put](const auto& v) { put(&v, sizeof v); };
  for (const Light& l : s.lights) {
    putValue(l.type);
    putValue(l.position);
    putValue(l.direction);
    putValue(l.shadows);
  }
  putValue(s.shadows.resolution);
  putValue(s.shadows.layers);
  putValue(s.shadows.density);
  putValue(s.shadows.lodCorrection);
  putValue(s.shadows.bias);
  putValue(s.shadows.pcf);
  putValue(s.shadows.lodScale);
  for (const Sphere& sp : s.spheres) {
    putValue(sp.center);
    putValue(sp.radius);
  }
  for (const Plane& pl : s.planes) put(&pl, sizeof pl);
  for (const MeshInstance& m : s.meshes) {
    k.held.push_back(m.mesh);
    putValue(m.transform);
  }
  for (const GroomInstance& g : s.grooms) {
    k.held.push_back(g.mesh);
    k.held.push_back(g.strands);
    putValue(g.transform);
    // the cage this frame deforms the hair mesh to (wind, cage animation): by value, since
    // every evaluation of a frame makes its own copy
    const std::size_t cage = g.deformed ? g.deformed->size() : 0;
    putValue(cage);
    if (cage) put(g.deformed->data(), cage * sizeof(glm::vec3));
  }
  putValue(o.lod);
  putValue(o.shadowLod);
  putValue(o.lodLambdaScale);
  putValue(o.shadowLodCorrection);
  putValue(o.ambientOcclusion);
  putValue(o.trueWidth);
  putValue(lodCorrection);
  putValue(o.shadowLodCamera);
  putValue(o.shadowResFromCamera);
  const std::size_t counts[4] = {s.lights.size(), s.spheres.size(), s.planes.size(),
                                 s.grooms.size()};
  putValue(counts);
  return k;
}

int ShadowMaps::mapResolution(int sceneResolution, float across) {
  // a texel per camera pixel across the grooms' bounding sphere, to the next power of two
  // (it changes an octave at a time, so a dolly rebuilds the maps seldom)
  int res = kMinResolution;
  while (res < sceneResolution && float(res) < across) res *= 2;
  return std::min(res, sceneResolution);
}

bool ShadowMaps::cameraCaps(const RenderOptions& options, bool cameraLod) {
  const bool lightLod = isOn(options.shadowLod, options.lod != Toggle::Off);
  return cameraLod && lightLod && options.shadowLodCamera != Toggle::Off;
}

bool ShadowMaps::needsRebuild(const Scene& s, const RenderOptions& options, bool lodCorrection,
                              const std::vector<GroomDraw>* draws) {
  Key key = keyOf(s, options, lodCorrection);
  // where the camera's LOD caps a groom's light passes, the groom's size on the camera's
  // screen (its bounding sphere's share of the image height) to half an octave: the maps
  // are kept while the camera moves within it
  const glm::mat4 w2v = worldToView(s.camera);
  const gpu::ClhViewGpu view = makeView(s.camera, s.width, s.height);
  // the grooms' largest diameter on the camera's screen, pixels (the map's resolution)
  float across = draws && options.shadowResFromCamera ? 0.0f : float(s.shadows.resolution);
  for (std::size_t k = 0; draws && k < draws->size(); ++k) {
    const GroomDraw& d = (*draws)[k];
    const bool lodOn = isOn(options.lod, d.groom->lodEnabled());
    const glm::vec3 lo = d.groom->boundsMin(), hi = d.groom->boundsMax();
    const glm::mat4& t = d.instance->transform;
    const glm::vec3 c = glm::vec3(t * glm::vec4(0.5f * (lo + hi), 1.0f));
    const float scale = std::max(
        {glm::length(glm::vec3(t[0])), glm::length(glm::vec3(t[1])), glm::length(glm::vec3(t[2]))});
    const float radius = 0.5f * glm::length(hi - lo) * scale;
    const float z = (w2v * glm::vec4(c, 1.0f)).z;
    const float share = z > radius ? view.fy * 2.0f * radius / z / float(s.height) : 1e30f;
    across = std::max(across, share * float(s.height));
    int bucket = 1 << 20;  // not capped
    if (cameraCaps(options, lodOn))
      bucket = share >= 1.0f ? 0 : static_cast<int>(std::floor(2.0f * std::log2(share)));
    const auto* b = reinterpret_cast<const unsigned char*>(&bucket);
    key.bytes.insert(key.bytes.end(), b, b + sizeof bucket);
  }
  planned_ = mapResolution(s.shadows.resolution, across);
  key.bytes.insert(key.bytes.end(), reinterpret_cast<const unsigned char*>(&planned_),
                   reinterpret_cast<const unsigned char*>(&planned_) + sizeof planned_);
  if (options.reuseShadows && valid_ && key == lastKey_) return false;
  // the maps are valid for this key once the rebuild is enqueued (the frame's next pass);
  // a frame that fails before it leaves them invalid
  valid_ = false;
  lastKey_ = std::move(key);
  return true;
}

std::vector<std::size_t> ShadowMaps::mappedLights(const Scene& s, std::size_t grooms) {
  std::vector<std::size_t> out;
  if (grooms == 0) return out;
  for (std::size_t i = 0; i < s.lights.size() && out.size() < CLH_MAX_SHADOWS; ++i)
    if (s.lights[i].shadows) out.push_back(i);
  return out;
}

void ShadowMaps::begin(const Scene& s, const RenderOptions& cameraOptions, bool lodCorrection,
                       const std::vector<GroomDraw>& grooms, const ViewDraw* camera,
                       Profiler* profiler) {
  grooms_ = grooms;
  totalSlots_ = grooms.size();
  ensureCapacity<cl_uint>(dev_, totals_, totalCap_, "shadow strand totals",
                          CLH_MAX_SHADOWS * std::max<std::size_t>(totalSlots_, 1));
  clear_.uints(totals_, CLH_MAX_SHADOWS * std::max<std::size_t>(totalSlots_, 1), 0u, "shadow",
               profiler);
  // the light's passes use LOD unless the caller turned it off explicitly
  ViewDraw& pass = lightDraw_;
  pass = ViewDraw{};
  pass.view = &lightView_;
  pass.lod =
      isOn(cameraOptions.shadowLod, cameraOptions.lod != Toggle::Off) ? Toggle::On : Toggle::Off;
  lightLambdaScale_ = cameraOptions.lodLambdaScale * s.shadows.lodScale;
  pass.lodLambdaScale = lightLambdaScale_;
  pass.lodStrandScale = pass.lodLambdaScale;
  pass.trueWidth = cameraOptions.trueWidth;
  pass.shadowLodCorrection = lodCorrection;
  // the camera's LOD records of the grooms it draws with LOD: the light passes draw no more
  // per bundle (lod.cl, lod_cap)
  capped_.assign(grooms.size(), 0);
  cameraAt_.assign(grooms.size(), 0);  // each draw's first record
  const bool anyLight =
      std::any_of(s.lights.begin(), s.lights.end(), [](const Light& l) { return l.shadows; });
  std::size_t records = 0;
  for (std::size_t k = 0; k < grooms.size() && camera && camera->view && anyLight; ++k) {
    const GroomDraw& d = grooms[k];
    const bool lodOn = isOn(cameraOptions.lod, d.groom->lodEnabled());
    if (!cameraCaps(cameraOptions, lodOn) || d.state->records == 0) continue;
    cameraAt_[k] = static_cast<std::uint32_t>(records);
    records += d.state->records;
    capped_[k] = 1;
  }
  if (records > 0)
    ensureCapacity<gpu::ClhLodRecord>(dev_, cameraLod_, cameraLodCap_, "the camera's LOD records",
                                      records);
  for (std::size_t k = 0; k < grooms.size(); ++k) {
    if (!capped_[k]) continue;
    const GroomDraw& d = grooms[k];
    if (!d.groom->prepare(*d.state, d.instance->transform, *camera)) {
      capped_[k] = 0;
      continue;
    }
    d.groom->lod(*d.state, *camera->view, profiler);
    // the camera's LOD records kept (16 bytes, four 32-bit words each)
    constexpr std::size_t recordWords = sizeof(gpu::ClhLodRecord) / 4;
    clear_.copyUints(d.state->lod, 0, cameraLod_, cameraAt_[k] * recordWords,
                     d.state->records * recordWords, "shadow", profiler);
  }
  params_.assign(CLH_MAX_SHADOWS, gpu::ClhShadowGpu{});
  slots_ = 0;
}

float ShadowMaps::worldBox(bool hair, glm::vec3& lo, glm::vec3& hi) const {
  lo = glm::vec3(1e30f);
  hi = glm::vec3(-1e30f);
  for (const GroomDraw& d : grooms_) {
    const glm::vec3 blo = hair ? d.groom->hairMin() : d.groom->boundsMin();
    const glm::vec3 bhi = hair ? d.groom->hairMax() : d.groom->boundsMax();
    for (int c = 0; c < 8; ++c) {
      glm::vec3 corner((c & 1) ? bhi.x : blo.x, (c & 2) ? bhi.y : blo.y, (c & 4) ? bhi.z : blo.z);
      glm::vec3 w = glm::vec3(d.instance->transform * glm::vec4(corner, 1.0f));
      lo = glm::min(lo, w);
      hi = glm::max(hi, w);
    }
  }
  return 0.5f * glm::length(hi - lo);
}

Camera ShadowMaps::lightCamera(const Light& light, float& dist, float& radius) const {
  // a pinhole at the light (directional: far away, narrow) framing all grooms' hair (its
  // measured box: a map's texels and layers spread over the hair, not the styling reach)
  glm::vec3 lo, hi;
  radius = worldBox(true, lo, hi);
  const glm::vec3 center = 0.5f * (lo + hi);
  Camera cam;
  cam.target = center;
  if (light.type == Light::Type::Point)
    cam.position = light.position;
  else
    cam.position = center + glm::normalize(light.direction) * (radius * 20.0f);
  dist = glm::length(cam.position - center);
  if (dist < 1e-6f) return cam;
  const glm::vec3 dir = (center - cam.position) / dist;
  cam.up = std::fabs(dir.y) > 0.95f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  cam.fovYDegrees = std::min(
      150.0f,
      2.0f * glm::degrees(std::atan(radius / std::max(dist - radius, radius * 0.05f))) * 1.05f);
  return cam;
}

void ShadowMaps::drawLight(const Scene& s, std::size_t lightIndex, SceneGpu& scene,
                           DispatchMode mode, Profiler* profiler) {
  const Light& light = s.lights[lightIndex];
  const int slot = slots_++;
  const int res = planned_ > 0 ? planned_ : s.shadows.resolution;
  ensureBuffers(res);
  const std::size_t plane = static_cast<std::size_t>(res) * res;
  float dist = 0.0f, radius = 0.0f;
  const Camera cam = lightCamera(light, dist, radius);
  if (dist < 1e-6f) return;  // a light at the grooms' center: no map, the slot stays unshadowed
  const gpu::ClhViewGpu lv = makeView(cam, res, res);
  upload(dev_, lightView_, &lv, 1);
  ViewDraw& pass = lightDraw_;
  // The map frames the hair, so a strand is wider in texels than across the bounds' sphere;
  // the light's LOD keeps the strands it drew across that sphere (the map's opacity comes from
  // its resolution, not from its strand count: DESIGN.md, "The maps frame the hair").
  glm::vec3 blo, bhi;
  const float boundsRadius = worldBox(false, blo, bhi);
  const float framing = boundsRadius > radius && radius > 0.0f ? radius / boundsRadius : 1.0f;
  pass.lodLambdaScale = lightLambdaScale_ * framing;
  pass.lodStrandScale = pass.lodLambdaScale;
  pass.worldToView = worldToView(cam);
  pass.nearZ = std::max(dist - radius, 1e-4f);
  pass.farZ = dist + radius;

  gpu::ClhShadowGpu& sh = params_[slot];
  std::memcpy(sh.world_to_view, lv.world_to_view, sizeof(sh.world_to_view));
  sh.fx = lv.fx;
  sh.fy = lv.fy;
  sh.cx = lv.cx;
  sh.cy = lv.cy;
  sh.width = sh.height = static_cast<gpu::clh_u32>(res);
  sh.offset = static_cast<gpu::clh_u32>(plane * slot);
  sh.density = s.shadows.density;
  for (int k = 0; k < 3; ++k) sh.bound[k] = s.shadows.layers[k];
  sh.bias = s.shadows.bias;
  sh.pcf = s.shadows.pcf ? 1u : 0u;
  sh.depth_near = pass.nearZ;
  sh.depth_far = pass.farZ;
  upload(dev_, one_[slot], &sh, 1);

  // the opaque scene and meshes from the light: their depth only
  const ViewTarget lightTarget{&lightView_, res, res};
  scene.drawOpaque(lightTarget, maps(), lightColor_, lightDepth_, false, profiler);
  clear_.copyUints(lightDepth_, 0, opaque_, plane * slot, plane, "shadow", profiler);
  // hair depth: the strand pass of every groom from the light into the light's G-buffer
  clear_.words(lightGBuffer_, plane * 2, ~std::uint64_t(0), "clear", profiler);
  StrandRaster rs;
  rs.view = &lightView_;
  rs.sceneDepth = &lightDepth_;
  rs.gbuffer = &lightGBuffer_;
  rs.counters = &counters_;
  rs.pixels = plane;
  // sized without a read-back unless the frame's mode asks for one; the kernels stop at
  // the scan's total either way
  rs.mode = mode == DispatchMode::Auto ? DispatchMode::OverLaunch : mode;
  std::vector<std::pair<const GroomDraw*, std::uint32_t>> drawn;
  for (std::size_t k = 0; k < grooms_.size(); ++k) {
    const GroomDraw& d = grooms_[k];
    if (!d.groom->prepare(*d.state, d.instance->transform, pass)) continue;
    d.groom->lod(*d.state, lightView_, profiler);
    if (capped_[k])
      stage_.capLod(d.state->lod, d.state->counts, d.state->offsets, cameraLod_, cameraAt_[k],
                    d.state->records, d.groom->storedStrands(), profiler);
    rs.strands =
        mode == DispatchMode::ReadBack ? d.groom->readTotal(*d.state) : d.groom->strandCount();
    drawn.push_back({&d, rs.strands});
    if (d.state->records > 0)
      clear_.copyUints(d.state->offsets, gpu::clh_lod_drawn_total_at(d.state->records), totals_,
                       static_cast<std::size_t>(slot) * totalSlots_ + k, 1, "shadow", profiler);
    d.groom->raster(*d.state, rs, profiler);
  }
  stage_.resolveDepth(one_[slot], lightGBuffer_, hair_, res, plane * CLH_MAX_SHADOWS, profiler);
  stage_.clearOpacity(one_[slot], opacity_, plane, plane * CLH_MAX_SHADOWS, profiler);
  // every instance keeps its own LOD records, so the opacity passes reuse them
  OpacityDraw op;
  op.lightView = &lightView_;
  op.opaqueDepth = &opaque_;
  op.shadow = &one_[slot];
  op.hairDepth = &hair_;
  op.opacity = &opacity_;
  op.texels = plane * CLH_MAX_SHADOWS;
  for (const auto& [d, strands] : drawn) d->groom->opacity(*d->state, op, strands, profiler);
}

void ShadowMaps::finish() {
  if (slots_ > 0) upload(dev_, all_, params_.data(), CLH_MAX_SHADOWS);
  if (res_ == 0) ensureBuffers(1);
  valid_ = true;
}

}  // namespace clhair
