// strand_file_gpu.cpp — see strand_file_gpu.h.
#include "groom/strand_file_gpu.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <glm/matrix.hpp>

#include "cl/buffers.h"
#include "clhair/lod_math.h"
#include "groom/ao_field.h"
#include "groom/diffusion_field.h"
#include "groom/groom_data.h"
#include "stages/view_math.h"

namespace clhair {

StrandFileGpu::StrandFileGpu(std::shared_ptr<const StrandGroom> groom, GroomStages& stages)
    : GroomGpu(stages.dev), groom_(std::move(groom)), stages_(stages) {
  const StrandGroom& sg = *groom_;
  const std::string what = "groom \"" + sg.name + "\"";
  validateStrandGroom(sg, what);
  data_ = prepareExplicit(sg);
  ExplicitData& d = data_;
  hairMin_ = d.boundsMin;
  hairMax_ = d.boundsMax;
  if (d.kids.count == 0) {
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (std::size_t s = 0; s + 1 < d.strandOffsets.size(); ++s) {
      const std::uint32_t a = d.strandOffsets[s], b = d.strandOffsets[s + 1];
      bool draws = false;
      for (std::uint32_t k = a + 1; k < b && !draws; ++k)
        draws = glm::vec3(d.points[k]) != glm::vec3(d.points[a]);
      for (std::uint32_t k = a; draws && k < b; ++k) {
        lo = glm::min(lo, glm::vec3(d.points[k]));
        hi = glm::max(hi, glm::vec3(d.points[k]));
      }
    }
    if (lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z) {
      hairMin_ = lo;
      hairMax_ = hi;
    }
  }
  gpu::ClhGroomGpu& p = base_;
  std::memset(&p, 0, sizeof(p));
  {
    // appearance and LOD fields exactly as a hair mesh fills them (groom_data.cpp), from a
    // mesh that carries only those; no styling
    HairMesh look;
    look.layerCount = 2;
    look.seed = sg.seed;
    look.appearance = sg.appearance;
    look.lod = sg.lod;
    fillGroomParams(look, GroomData{}, p);
  }
  p.bundle_count = static_cast<gpu::clh_u32>(d.chunks.size());
  p.layer_count = 0;
  p.vertex_count = 0;
  p.has_tangents = 0;
  p.control_points = CLH_MAX_CONTROL_POINTS;                    // C_full of the chunk LOD: step 1
  p.total_strands = static_cast<gpu::clh_u32>(d.drawnStrands);  // children included
  const std::size_t K = d.chunks.size();
  // per-point file colour and thickness follow the points in the same buffer
  // (kernels/strands_explicit.cl reads them at point_count + k)
  p.look[2] = d.fileColor ? 1.0f : 0.0f;
  // per-point opacity without file thickness scales the groom's width (look[3] < 0); a
  // uniform transparency with neither narrows the width itself
  if (d.fileOpacity && !d.fileThickness) p.look[3] = -1.0f;
  if (!d.fileOpacity && !d.fileThickness) p.strand_width *= 1.0f - sg.appearance.transparency;
  // the AO field's density, while the points and their file look are on the host
  aoDensity_ =
      splatAoDensity(d, sg.appearance.strandWidth * (1.0f - sg.appearance.transparency),
                     d.totalStrands > 0 ? float(d.drawnStrands) / float(d.totalStrands) : 1.0f);
  if (!d.fileLook.empty()) d.points.insert(d.points.end(), d.fileLook.begin(), d.fileLook.end());
  std::vector<glm::vec4>().swap(d.fileLook);
  pointWords_ = d.points.size();
  points_ =
      makeBuffer<cl_float4>(dev_, what + " strand points (" + std::to_string(d.totalPoints) + ")",
                            d.points.size(), reinterpret_cast<const cl_float4*>(d.points.data()));
  strandOffsets_ =
      makeBuffer(dev_, what + " strand offsets", d.strandOffsets.size(), d.strandOffsets.data());
  uv_ = d.uv.empty() ? makeBuffer<cl_uint>(dev_, what + " root uv", 1)
                     : makeBuffer(dev_, what + " root uv", d.uv.size(), d.uv.data());
  chunks_ = makeBuffer<cl_uint4>(dev_, what + " chunk table", K,
                                 reinterpret_cast<const cl_uint4*>(d.chunks.data()));
  chunkBounds_ = makeBuffer<cl_float4>(dev_, what + " chunk bounds", 2 * K,
                                       reinterpret_cast<const cl_float4*>(d.chunkBounds.data()));
  kids_ = makeBuffer<gpu::ClhChildrenGpu>(dev_, what + " children", 1, &d.kids);
  neighbours_ = d.neighbours.empty() ? makeBuffer<cl_uint>(dev_, what + " guide neighbours", 1)
                                     : makeBuffer(dev_, what + " guide neighbours",
                                                  d.neighbours.size(), d.neighbours.data());
  std::vector<glm::vec4>().swap(d.points);  // on the device now
}

std::unique_ptr<GroomInstanceGpu> StrandFileGpu::makeInstance() {
  return newInstance(groom_->name, static_cast<std::uint32_t>(data_.chunks.size()), base_);
}

std::uint64_t StrandFileGpu::sharedBytes() const {
  std::uint64_t sum = 0;
  for (const cl::Buffer* b :
       {&points_, &strandOffsets_, &uv_, &chunks_, &chunkBounds_, &kids_, &neighbours_})
    sum += bufferBytes(*b);
  return sum;
}

ExplicitStage::Inputs StrandFileGpu::inputs(GroomInstanceGpu& inst) const {
  ExplicitStage::Inputs in;
  in.groom = &inst.groom;
  in.points = &points_;
  in.strandOffsets = &strandOffsets_;
  in.uv = &uv_;
  in.chunks = &chunks_;
  in.chunkBounds = &chunkBounds_;
  in.kids = &kids_;
  in.neighbours = &neighbours_;
  in.neighbourWords = std::max<std::uint64_t>(data_.neighbours.size(), 1);
  in.children = data_.kids.count;
  in.lod = &inst.lod;
  in.counts = &inst.counts;
  in.offsets = &inst.offsets;
  in.chunkCount = static_cast<std::uint32_t>(data_.chunks.size());
  in.strandCount = static_cast<std::uint32_t>(data_.totalStrands);
  in.pointCount = static_cast<std::uint32_t>(data_.totalPoints);
  in.pointWords = pointWords_;
  in.hasUv = !data_.uv.empty();
  return in;
}

bool StrandFileGpu::prepare(GroomInstanceGpu& inst, const glm::mat4& objToWorld,
                            const ViewDraw& pass) {
  gpu::ClhGroomGpu& p = inst.params;
  const glm::mat4 o2v = pass.worldToView * objToWorld;
  storeMat34(p.obj_to_view, o2v);
  storeMat34(p.obj_to_world, objToWorld);
  if (!depthRange(data_.boundsMin, data_.boundsMax, o2v, p.depth_near, p.depth_far)) return false;
  if (pass.nearZ > 0.0f) {
    p.depth_near = pass.nearZ;
    p.depth_far = pass.farZ;
  }
  const StrandGroom& sg = *groom_;
  p.lod_enabled = isOn(pass.lod, sg.lod.enabled) ? 1u : 0u;
  p.lod_lambda = sg.lod.lambda * pass.lodLambdaScale;
  p.lod_strands_px = sg.lod.strandsPerPixel * pass.lodStrandScale;
  p.hit_diameter_px = pass.trueWidth ? 0.0f : sg.appearance.minHitDiameterPx;
  p.shadow_lod_correction = pass.shadowLodCorrection ? 1u : 0u;
  if (data_.fileThickness) {
    // file thickness is in object units: scale it like the points (uniform part)
    const float scale = std::cbrt(std::fabs(glm::determinant(glm::mat3(objToWorld))));
    p.look[3] = scale;
    p.strand_width = std::max(data_.meanThickness * scale, 1e-9f);  // LOD and shadow estimates
  }
  // a faint groom's centre hits a pixel wide, with the alpha of its true width
  p.faint_width_px1 = 0.0f;
  if (pass.widenFaint && !pass.trueWidth && p.hit_diameter_px <= 0.0f && !data_.fileThickness &&
      faint(o2v, pass.pixels)) {
    p.hit_diameter_px = kFaintHitDiameterPx;
    p.faint_width_px1 = pass.pixels.fy * p.strand_width;
  }
  uploadChanged(dev_, inst.groom, inst.sent, &p, 1);
  return true;
}

bool StrandFileGpu::faint(const glm::mat4& objToView, const FaintView& view) {
  // the estimate projects up to kFaintMaxSampled strands: once per placement and camera
  if (!(faintKnown_ && objToView == faintView_ && view == faintPixels_)) {
    faintKnown_ = true;
    faintView_ = objToView;
    faintPixels_ = view;
    faint_ = estimateFaint(*groom_, objToView, view).faint();
  }
  return faint_;
}

const AoField* StrandFileGpu::aoField(const Scene& scene, const glm::mat4& objToWorld) {
  if (aoDensity_.density.empty()) return nullptr;
  // the placement: the transform and the occluders' geometry; a frame placed as the last
  // one takes its field without marking the grid again
  std::string placement(reinterpret_cast<const char*>(&objToWorld), sizeof(objToWorld));
  for (const Sphere& sp : scene.spheres) {
    placement.append(reinterpret_cast<const char*>(&sp.center), sizeof(sp.center));
    placement.append(reinterpret_cast<const char*>(&sp.radius), sizeof(sp.radius));
  }
  for (const MeshInstance& mi : scene.meshes) {
    const void* mesh = mi.mesh.get();
    placement.append(reinterpret_cast<const char*>(&mesh), sizeof(mesh));
    placement.append(reinterpret_cast<const char*>(&mi.transform), sizeof(mi.transform));
  }
  if (lastField_ && placement == lastPlacement_)
    return withDiffusedLight(scene, objToWorld, placement);
  placedDensity_ = withOccluders(aoDensity_, scene, objToWorld);
  const AoDensity& d = placedDensity_;
  std::uint64_t sum = 1469598103934665603ull;  // FNV-1a over the grid
  for (std::uint32_t v : d.density) sum = (sum ^ v) * 1099511628211ull;
  std::unique_ptr<AoField>& f = aoFields_[sum];
  if (!f) {
    if (aoFields_.size() > 8) {  // a moving groom: keep the latest placements only
      aoFields_.clear();
      lastField_ = nullptr;
      return aoField(scene, objToWorld);
    }
    f = std::make_unique<AoField>(bakeAoField(dev_, stages_.ao, d));
  }
  lastPlacement_ = placement;
  lastField_ = f.get();
  return withDiffusedLight(scene, objToWorld, placement);
}

const AoField* StrandFileGpu::withDiffusedLight(const Scene& scene, const glm::mat4& objToWorld,
                                                const std::string& placement) {
  if (!data_.fileColor || !groom_ || groom_->colors.empty() || !lastField_ ||
      lastField_->host.size() != lastField_->voxels())
    return lastField_;
  const glm::mat4 inv = glm::inverse(objToWorld);
  std::vector<DiffusionLight> lights;
  std::string key = placement;
  int mapped = 0;  // the lights with a map: the first CLH_MAX_SHADOWS that ask for one
  for (const Light& l : scene.lights) {
    if (!l.shadows || mapped >= CLH_MAX_SHADOWS) continue;
    ++mapped;
    DiffusionLight dl;
    dl.point = l.type == Light::Type::Point;
    dl.at = dl.point ? glm::vec3(inv * glm::vec4(l.position, 1.0f))
                     : glm::normalize(glm::vec3(inv * glm::vec4(l.direction, 0.0f)));
    dl.radiance = l.color * l.intensity;
    key.append(reinterpret_cast<const char*>(&dl), sizeof(dl));
    lights.push_back(dl);
  }
  if (lights.empty()) return lastField_;
  if (diffused_ && key == diffusedKey_) return diffused_.get();
  glm::dvec3 sum(0.0);
  for (const glm::vec3& c : groom_->colors) sum += glm::dvec3(c);
  const glm::vec3 albedo = glm::vec3(sum / static_cast<double>(groom_->colors.size()));
  const float scale = std::cbrt(std::fabs(glm::determinant(glm::mat3(objToWorld))));
  const std::vector<glm::vec3> rgb = diffuseGroomLight(placedDensity_, albedo, lights, scale);
  const std::size_t n = lastField_->voxels();
  std::vector<float> planes(4 * n);
  std::copy(lastField_->host.begin(), lastField_->host.end(), planes.begin());
  for (std::size_t i = 0; i < n && i < rgb.size(); ++i)
    for (int c = 0; c < 3; ++c) planes[(1 + c) * n + i] = rgb[i][c];
  diffused_ = std::make_unique<AoField>(*lastField_);
  diffused_->flags = 3u;
  diffused_->values =
      makeBuffer<cl_float>(dev_, "the AO field with diffused light", planes.size(), planes.data());
  diffusedKey_ = key;
  return diffused_.get();
}

void StrandFileGpu::lod(GroomInstanceGpu& inst, const cl::Buffer& view, Profiler* profiler) {
  stages_.explicitStrands.lod(inputs(inst), view, profiler);
}

void StrandFileGpu::raster(GroomInstanceGpu& inst, const StrandRaster& r, Profiler* profiler) {
  stages_.explicitStrands.raster(inputs(inst), r, profiler);
}

void StrandFileGpu::opacity(GroomInstanceGpu& inst, const OpacityDraw& o, std::uint32_t strands,
                            Profiler* profiler) {
  stages_.explicitStrands.opacity(inputs(inst), o, strands, profiler);
}

bool StrandFileGpu::motion(GroomInstanceGpu& inst, const GroomInstance& previous,
                           const MotionDraw& m, const StrandRaster& r, Profiler* profiler) {
  const std::shared_ptr<const StrandGroom>& prev = previous.strands;
  if (!prev) return false;
  if (prev != prevGroom_) {
    const StrandGroom& before = *prev;
    if (before.pointCounts != groom_->pointCounts) return false;  // no point correspondence
    std::vector<std::size_t> first(before.pointCounts.size() + 1, 0);
    for (std::size_t s = 0; s < before.pointCounts.size(); ++s)
      first[s + 1] = first[s] + before.pointCounts[s];
    if (first.back() != before.points.size()) return false;
    std::vector<glm::vec4> pts(std::max<std::size_t>(data_.totalPoints, 1));
    for (std::size_t st = 0; st < data_.totalStrands; ++st) {
      const std::uint32_t src = data_.sourceStrand[st];
      const std::uint32_t at = data_.strandOffsets[st], n = data_.strandOffsets[st + 1] - at;
      if (src >= before.pointCounts.size() || n != before.pointCounts[src]) return false;
      for (std::uint32_t k = 0; k < n; ++k)
        pts[at + k] = glm::vec4(before.points[first[src] + k],
                                static_cast<float>(k) / static_cast<float>(n - 1));
    }
    prevPoints_ = makeBuffer<cl_float4>(dev_, "groom \"" + groom_->name + "\" previous points",
                                        pts.size(), reinterpret_cast<const cl_float4*>(pts.data()));
    prevGroom_ = prev;
  }
  stages_.explicitStrands.motion(inputs(inst), prevPoints_, m, r, profiler);
  return true;
}

// The strands as drawn at LOD value `lod`, every chunk at that value: the records
// lod_chunks would write, computed here.
StrandSet StrandFileGpu::exportStrands(float lod) {
  std::unique_ptr<GroomInstanceGpu> inst = makeInstance();
  inst->params.lod_enabled = 0;
  uploadChanged(dev_, inst->groom, inst->sent, &inst->params, 1);
  const std::size_t K = data_.chunks.size();
  const auto n = static_cast<gpu::clh_u32>(K);
  std::vector<gpu::ClhLodRecord> records(K);
  std::vector<cl_uint> offsets(gpu::clh_lod_offsets_length(n), 0);
  gpu::clh_u32 drawn = 0;
  for (std::size_t c = 0; c < K; ++c) {
    const glm::uvec4& chunk = data_.chunks[c];
    float delta;
    std::memcpy(&delta, &chunk.z, 4);  // chunk table: first strand, count, delta bits
    records[c] = gpu::clh_lod_record_at(lod, chunk.y, delta, 3u, CLH_MAX_CONTROL_POINTS,
                                        groom_->lod.morphWindow);
    offsets[c] = drawn;
    drawn += records[c].strands;
  }
  offsets[gpu::clh_lod_drawn_total_at(n)] = drawn;
  offsets[gpu::clh_lod_visible_total_at(n)] = static_cast<cl_uint>(data_.drawnStrands);
  upload(dev_, inst->lod, records.data(), records.size());
  upload(dev_, inst->offsets, offsets.data(), offsets.size());
  const std::uint32_t total = drawn;
  // child c of stored strand s is drawn strand s + c S, its points after c copies of P
  const std::size_t P = data_.totalPoints, S = data_.totalStrands;
  const std::size_t copies = std::size_t(data_.kids.count) + 1;
  cl::Buffer points = makeBuffer<cl_float4>(dev_, "exported strand points", P * copies);
  cl::Buffer tangents = makeBuffer<cl_float4>(dev_, "exported strand tangents", P * copies);
  std::vector<cl_uint> counts(S * copies, 0);
  cl::Buffer countBuf =
      makeBuffer<cl_uint>(dev_, "exported strand point counts", S * copies, counts.data());
  stages_.explicitStrands.exportStrands(inputs(*inst), total, points, tangents, countBuf, nullptr);
  std::vector<cl_float4> p(P * copies), t(P * copies);
  readBack(dev_, "exported strands", points, p.data(), P * copies);
  readBack(dev_, "exported strands", tangents, t.data(), P * copies);
  readBack(dev_, "exported strands", countBuf, counts.data(), S * copies);
  // per-point file colour and thickness follow the points in the same buffer
  std::vector<cl_float4> look;
  if (pointWords_ >= 2 * P) {
    look.resize(P);
    readBack(dev_, "strand file colours", points_, look.data(), P, P);
  }
  StrandSet out;
  for (std::size_t id = 0; id < S * copies; ++id) {
    const std::uint32_t M = counts[id];
    if (M == 0) continue;
    const std::size_t st = id % S, child = id / S;
    const std::size_t first = data_.strandOffsets[st] + child * P;
    out.pointCounts.push_back(M);
    out.bundleOf.push_back(static_cast<std::uint32_t>(st / data_.chunkGuides));
    out.sourceStrand.push_back(data_.sourceStrand[st]);
    // the words' u, v as strands_explicit.cl sets them: stored root uv or a per-strand hash
    float u, v;
    if (!data_.uv.empty()) {
      u = static_cast<float>(data_.uv[st] & 0xFFFFu) / 65535.0f;
      v = static_cast<float>(data_.uv[st] >> 16) / 65535.0f;
    } else {
      const gpu::clh_u32 h = gpu::clh_hash2(base_.seed, static_cast<gpu::clh_u32>(id));
      u = gpu::clh_u01(h);
      v = gpu::clh_u01(gpu::clh_hash(h));
    }
    out.uv.insert(out.uv.end(), {u, v});
    for (std::uint32_t j = 0; j < M; ++j) {
      const cl_float4& q = p[first + j];
      const cl_float4& tq = t[first + j];
      out.points.insert(out.points.end(), {q.s[0], q.s[1], q.s[2]});
      out.tangents.insert(out.tangents.end(), {tq.s[0], tq.s[1], tq.s[2]});
      out.w.push_back(q.s[3]);
      out.ao.push_back(tq.s[3]);
      if (!look.empty()) {  // a child carries its guide's look
        const cl_float4& l = look[data_.strandOffsets[st] + j];
        out.look.insert(out.look.end(), {l.s[0], l.s[1], l.s[2], l.s[3]});
      }
    }
  }
  return out;
}

}  // namespace clhair
