// hair_mesh_gpu.cpp — see hair_mesh_gpu.h.
#include "groom/hair_mesh_gpu.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>

#include "cl/buffers.h"
#include "clhair/lod_math.h"
#include "stages/ao_stage.h"
#include "stages/view_math.h"

namespace clhair {

namespace {
constexpr std::uint32_t kMinRootSet = 1024;
constexpr std::uint32_t kMaxRootSet = 1u << 16;
}  // namespace

const RootSetsGpu::Set& RootSetsGpu::forBundle(Device::Impl& dev, std::uint32_t strands) {
  if (strands > kMaxRootSet)
    throw Error("a bundle requests " + std::to_string(strands) + " strands; at most " +
                std::to_string(kMaxRootSet) + " per bundle are supported (split its scalp face)");
  std::uint32_t size = kMinRootSet;
  while (size < strands) size <<= 1;
  Set& s = sets_[size];
  if (s.size == 0) {
    const RootSets r = makeRootSets(size);
    s.quad = makeBuffer<glm::vec2>(dev, "root sample set", r.quad.size(), r.quad.data());
    s.triangle =
        makeBuffer<glm::vec2>(dev, "root sample set", r.triangle.size(), r.triangle.data());
    s.size = size;
  }
  return s;
}

HairMeshGpu::HairMeshGpu(std::shared_ptr<const HairMesh> mesh, GroomStages& stages, bool bakeAo)
    : GroomGpu(stages.dev), mesh_(std::move(mesh)), stages_(stages) {
  const HairMesh& m = *mesh_;
  data_ = prepareGroom(m);
  if (bakeAo && m.ao.empty()) {
    std::vector<float> ao = HairMeshGpu::bakeAo(m, stages_);
    for (std::size_t i = 0; i < ao.size() && i < data_.vertices.size(); ++i)
      data_.vertices[i].tan[3] = ao[i];
  }
  // the light maps frame the hair, not the bounds' styling reach (a groom built for a bake
  // or an export draws no maps and measures nothing)
  hairMin_ = data_.boundsMin;
  hairMax_ = data_.boundsMax;
  if (bakeAo) {
    const auto [lo, hi] = hairExtent(m, stages_);
    if (lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z) {
      hairMin_ = lo;
      hairMax_ = hi;
    }
  }
  ao_.resize(data_.vertices.size());
  for (std::size_t i = 0; i < ao_.size(); ++i) ao_[i] = data_.vertices[i].tan[3];
  std::memset(&base_, 0, sizeof(base_));
  fillGroomParams(m, data_, base_);
  hasTangents_ = base_.has_tangents != 0;
  roots_ = &stages_.roots.forBundle(dev_, data_.maxBundleStrands);
  base_.root_set_size = roots_->size;
  const std::string what = "groom \"" + m.name + "\"";
  vertices_ =
      makeBuffer(dev_, what + " hair-mesh vertices", data_.vertices.size(), data_.vertices.data());
  bundles_ = makeBuffer(dev_, what + " bundles", data_.bundles.size(), data_.bundles.data());
}

std::unique_ptr<GroomInstanceGpu> HairMeshGpu::makeInstance() {
  return newInstance(mesh_->name, static_cast<std::uint32_t>(data_.bundles.size()), base_);
}

std::uint64_t HairMeshGpu::sharedBytes() const {
  return bufferBytes(vertices_) + bufferBytes(bundles_);
}

StrandStage::Inputs HairMeshGpu::inputs(const GroomInstanceGpu& inst) const {
  StrandStage::Inputs in;
  in.groom = &inst.groom;
  in.bundles = &bundles_;
  in.vertices = &vertices_;
  in.lod = &inst.lod;
  in.offsets = &inst.offsets;
  in.rootsQuad = &roots_->quad;
  in.rootsTri = &roots_->triangle;
  in.bundleCount = static_cast<std::uint32_t>(data_.bundles.size());
  in.vertexTotal = data_.vertices.size();
  in.rootSetSize = roots_->size;
  return in;
}

bool HairMeshGpu::prepare(GroomInstanceGpu& inst, const glm::mat4& objToWorld,
                          const ViewDraw& pass) {
  gpu::ClhGroomGpu& p = inst.params;
  const glm::mat4 o2v = pass.worldToView * objToWorld;
  storeMat34(p.obj_to_view, o2v);
  storeMat34(p.obj_to_world, objToWorld);
  if (!depthRange(data_.boundsMin, data_.boundsMax, o2v, p.depth_near, p.depth_far)) return false;
  if (pass.nearZ > 0.0f) {  // a G-buffer shared by several grooms needs one depth mapping
    p.depth_near = pass.nearZ;
    p.depth_far = pass.farZ;
  }
  const HairMesh& mesh = *mesh_;
  p.lod_enabled = isOn(pass.lod, mesh.lod.enabled) ? 1u : 0u;
  p.lod_lambda = mesh.lod.lambda * pass.lodLambdaScale;
  p.lod_strands_px = mesh.lod.strandsPerPixel * pass.lodStrandScale;
  p.total_strands = static_cast<gpu::clh_u32>(data_.totalStrands);
  p.shadow_lod_correction = pass.shadowLodCorrection ? 1u : 0u;
  p.hit_diameter_px = pass.trueWidth ? 0.0f : mesh.appearance.minHitDiameterPx;
  p.has_tangents = hasTangents_ ? 1u : 0u;
  uploadChanged(dev_, inst.groom, inst.sent, &p, 1);
  // the styling reach in view units: the object-space margin times the largest axis scale
  const float scale =
      std::max({glm::length(glm::vec3(objToWorld[0])), glm::length(glm::vec3(objToWorld[1])),
                glm::length(glm::vec3(objToWorld[2]))});
  inst.reach = data_.styleMargin * scale;
  return true;
}

void HairMeshGpu::lod(GroomInstanceGpu& inst, const cl::Buffer& view, Profiler* profiler) {
  LodStage::Params lp;
  lp.groom = &inst.groom;
  lp.view = &view;
  lp.bundles = &bundles_;
  lp.vertices = &vertices_;
  lp.reach = inst.reach;
  lp.lod = &inst.lod;
  lp.counts = &inst.counts;
  lp.offsets = &inst.offsets;
  lp.bundleCount = static_cast<std::uint32_t>(data_.bundles.size());
  lp.vertexTotal = data_.vertices.size();
  stages_.lod.enqueue(lp, profiler);
}

void HairMeshGpu::raster(GroomInstanceGpu& inst, const StrandRaster& r, Profiler* profiler) {
  stages_.strands.raster(inputs(inst), r, profiler);
}

void HairMeshGpu::opacity(GroomInstanceGpu& inst, const OpacityDraw& o, std::uint32_t strands,
                          Profiler* profiler) {
  stages_.strands.opacity(inputs(inst), o, strands, profiler);
}

void HairMeshGpu::useAo(bool on) {
  if (aoUploaded_ == on) return;
  std::vector<gpu::ClhMeshVertex> v = data_.vertices;
  for (std::size_t i = 0; i < v.size(); ++i) v[i].tan[3] = on ? ao_[i] : 1.0f;
  upload(dev_, vertices_, v.data(), v.size());
  aoUploaded_ = on;
}

void HairMeshGpu::deform(const std::shared_ptr<const std::vector<glm::vec3>>& cage) {
  if (cage == cage_) return;
  const HairMesh& m = *mesh_;
  GroomData d;
  if (cage) {
    if (cage->size() != m.positions.size())
      throw Error("groom \"" + m.name + "\": a cage of " + std::to_string(cage->size()) +
                  " vertices for a hair mesh of " + std::to_string(m.positions.size()) +
                  " layer vertices");
    d = movedRecords(*cage);
  } else {
    d = prepareGroom(m);
  }
  for (std::size_t i = 0; i < d.vertices.size(); ++i)
    d.vertices[i].tan[3] = aoUploaded_ ? ao_[i] : 1.0f;
  upload(dev_, vertices_, d.vertices.data(), d.vertices.size());
  // ao_ keeps the rest pose's AO for useAo
  for (std::size_t i = 0; i < d.vertices.size(); ++i) d.vertices[i].tan[3] = ao_[i];
  data_.vertices = std::move(d.vertices);
  data_.boundsMin = d.boundsMin;
  data_.boundsMax = d.boundsMax;
  data_.styleMargin = d.styleMargin;
  hasTangents_ = !cage && !m.tangents.empty();
  moved_ = cage && *cage != m.positions;
  cage_ = cage;
}

bool HairMeshGpu::rasterViews(GroomInstanceGpu& inst, const StrandRaster& r,
                              const cl::Buffer& viewGrooms, const cl::Buffer& views,
                              std::uint32_t count, Profiler* profiler) {
  stages_.strands.rasterViews(inputs(inst), r, viewGrooms, views, count, profiler);
  return true;
}

bool HairMeshGpu::rasterStill(GroomInstanceGpu& inst, const StrandRaster& r, std::uint64_t still,
                              std::uint32_t subset, std::uint32_t pass, Profiler* profiler) {
  if (r.curve || r.points || r.cover) return false;
  StoredStrands& s = inst.stored;
  if (s.still != still) {
    s.still = still;
    s.fits = storeStill(inst, profiler);
  }
  if (!s.fits) return false;
  StrandStage::Inputs in = inputs(inst);
  in.lod = &s.lod;
  in.offsets = &s.offsets;
  stages_.strands.rasterStored(in, r, s, profiler, subset, pass);
  return true;
}

bool HairMeshGpu::storeStill(GroomInstanceGpu& inst, Profiler* profiler) {
  StoredStrands& s = inst.stored;
  const std::uint32_t B = static_cast<std::uint32_t>(data_.bundles.size());
  const std::uint32_t scanLength = gpu::clh_lod_offsets_length(B);
  std::vector<gpu::ClhLodRecord> records(B);
  std::vector<std::uint32_t> scan(scanLength);
  // one host wait: the queue is in order, so the scan's blocking read finds the records read
  readBackAsync(dev_, "the still's LOD records", inst.lod, records.data(), B);
  readBack(dev_, "the still's strand offsets", inst.offsets, scan.data(), scanLength);
  // the first point of each bundle's strands: its drawn strands times their control points
  const std::uint32_t total = scan[gpu::clh_lod_drawn_total_at(B)];
  std::vector<std::uint32_t> base(std::max<std::uint32_t>(B, 1), 0);
  std::uint64_t points = 0;
  for (std::uint32_t b = 0; b < B; ++b) {
    base[b] = static_cast<std::uint32_t>(std::min<std::uint64_t>(points, 0xffffffffu));
    const std::uint32_t end = b + 1 < B ? scan[b + 1] : total;
    const std::uint32_t drawn = std::min(records[b].strands, end > scan[b] ? end - scan[b] : 0u);
    const std::uint32_t C =
        std::clamp<std::uint32_t>(records[b].control_points, 2u, CLH_MAX_CONTROL_POINTS);
    points += std::uint64_t(drawn) * C;
  }
  // where the device's memory allows: each plane within one allocation, all of them within
  // a quarter of the device's memory
  const std::uint64_t plane = points * 4 * sizeof(float);
  const std::uint64_t all = 2 * plane + std::uint64_t(total) * 2 * sizeof(float);
  if (points > 0xffffffffull || plane > dev_.info.maxAlloc || all > dev_.info.globalMem / 4)
    return false;
  s.pointCount = points;
  s.strands = total;
  ensureCapacity<gpu::ClhLodRecord>(dev_, s.lod, s.lodCap, "stored LOD records",
                                    std::max<std::uint32_t>(B, 1));
  ensureCapacity<cl_uint>(dev_, s.offsets, s.offsetsCap, "stored strand offsets", scanLength);
  ensureCapacity<cl_uint>(dev_, s.pointBase, s.baseCap, "stored point bases", base.size());
  ensureCapacity<cl_float4>(dev_, s.points, s.pointCap, "stored points",
                            std::max<std::uint64_t>(points, 1));
  ensureCapacity<cl_float4>(dev_, s.tangents, s.tangentCap, "stored tangents",
                            std::max<std::uint64_t>(points, 1));
  ensureCapacity<cl_float2>(dev_, s.uvs, s.uvCap, "stored root coordinates",
                            std::max<std::uint32_t>(total, 1));
  upload(dev_, s.lod, records.data(), B);
  upload(dev_, s.offsets, scan.data(), scanLength);
  upload(dev_, s.pointBase, base.data(), base.size());
  StrandStage::Inputs in = inputs(inst);
  in.lod = &s.lod;
  in.offsets = &s.offsets;
  stages_.strands.store(in, s, profiler);
  return true;
}

GroomData HairMeshGpu::movedRecords(const std::vector<glm::vec3>& cage) const {
  const HairMesh& m = *mesh_;
  HairMesh moved;
  moved.layerCount = m.layerCount;
  moved.vertexCount = m.vertexCount;
  moved.faces = m.faces;
  moved.uv = m.uv;
  moved.positions = cage;
  moved.w = m.w;
  moved.strandCount = m.strandCount;
  moved.seed = m.seed;
  moved.style = m.style;
  return prepareGroom(moved);
}

bool HairMeshGpu::motion(GroomInstanceGpu& inst, const GroomInstance& previous, const MotionDraw& m,
                         const StrandRaster& r, Profiler* profiler) {
  if (hasTangents_) return false;
  const std::shared_ptr<const std::vector<glm::vec3>>& cage = previous.deformed;
  if (cage && cage->size() != mesh_->positions.size())
    throw Error("groom \"" + mesh_->name + "\": the previous frame's cage has " +
                std::to_string(cage->size()) + " vertices for a hair mesh of " +
                std::to_string(mesh_->positions.size()) + " layer vertices");
  if (!prevValid_ || cage != prevCage_) {
    const GroomData d = movedRecords(cage ? *cage : mesh_->positions);
    if (!prevVertices_())
      prevVertices_ = makeBuffer(dev_, "groom \"" + mesh_->name + "\" previous layer vertices",
                                 d.vertices.size(), d.vertices.data());
    else
      upload(dev_, prevVertices_, d.vertices.data(), d.vertices.size());
    prevCage_ = cage;
    prevValid_ = true;
  }
  stages_.strands.motion(inputs(inst), prevVertices_, m, r, profiler);
  return true;
}

// lod = 1: full detail (the LOD pass with LOD off and an unbounded reach keeps every
// bundle); lod < 1: every bundle at that LOD value, records computed here.
HairMeshGpu::Exported HairMeshGpu::exportOnDevice(GroomInstanceGpu& inst, float lod) {
  inst.params.lod_enabled = 0;
  uploadChanged(dev_, inst.groom, inst.sent, &inst.params, 1);
  Exported e;
  const std::size_t B = data_.bundles.size();
  if (lod >= 1.0f) {
    // The view buffer outlives the pass: Oclgrind 21.10 gives a released buffer's slot, with
    // its uninitialised-memory shadow sized for the old buffer, to the next allocation (here
    // the exported points), whose kernel writes past that size would stay uninitialised.
    const gpu::ClhViewGpu v = makeView(Camera{}, 1, 1);
    if (!exportView_())
      exportView_ = makeBuffer<gpu::ClhViewGpu>(dev_, "export view parameters", 1);
    upload(dev_, exportView_, &v, 1);
    inst.reach = 1e30f;
    this->lod(inst, exportView_, nullptr);
    e.total = readTotal(inst);
    if (e.total != data_.totalStrands)
      throw Error("strand export: the LOD pass kept " + std::to_string(e.total) + " of " +
                  std::to_string(data_.totalStrands) + " strands");
  } else {
    // the records and scan lod_bundles would write with every bundle at LOD value `lod`
    const HairMesh& mesh = *mesh_;
    const auto n = static_cast<gpu::clh_u32>(B);
    const auto layers = static_cast<gpu::clh_u32>(mesh.layerCount);
    const gpu::clh_u32 cmax = fullDetailControlPoints(mesh);
    std::vector<gpu::ClhLodRecord> records(B);
    std::vector<cl_uint> offsets(gpu::clh_lod_offsets_length(n), 0);
    gpu::clh_u32 drawn = 0;
    for (std::size_t b = 0; b < B; ++b) {
      const gpu::ClhBundle& bundle = data_.bundles[b];
      records[b] = gpu::clh_lod_record_at(lod, bundle.strand_count, bundle.lod_delta, layers, cmax,
                                          mesh.lod.morphWindow);
      offsets[b] = drawn;
      drawn += records[b].strands;
    }
    offsets[gpu::clh_lod_drawn_total_at(n)] = drawn;
    offsets[gpu::clh_lod_visible_total_at(n)] =
        static_cast<cl_uint>(data_.totalStrands);  // none culled
    e.total = drawn;
    upload(dev_, inst.lod, records.data(), records.size());
    upload(dev_, inst.offsets, offsets.data(), offsets.size());
  }
  if (e.total == 0) return e;
  const std::size_t slots = static_cast<std::size_t>(e.total) * CLH_MAX_CONTROL_POINTS;
  e.points = makeBuffer<cl_float4>(dev_, "exported strand points", slots);
  e.tangents = makeBuffer<cl_float4>(dev_, "exported strand tangents", slots);
  e.counts = makeBuffer<cl_uint>(dev_, "exported strand point counts", e.total);
  stages_.strands.exportStrands(inputs(inst), e.total, e.points, e.tangents, e.counts, nullptr);
  return e;
}

StrandSet HairMeshGpu::exportStrands(float lod) {
  std::unique_ptr<GroomInstanceGpu> inst = makeInstance();
  Exported e = exportOnDevice(*inst, lod);
  StrandSet out;
  const std::uint32_t total = e.total;
  if (total == 0) return out;
  const std::size_t slots = static_cast<std::size_t>(total) * CLH_MAX_CONTROL_POINTS;
  std::vector<cl_float4> p(slots), t(slots);
  out.pointCounts.resize(total);
  readBack(dev_, "exported strands", e.points, p.data(), slots);
  readBack(dev_, "exported strands", e.tangents, t.data(), slots);
  readBack(dev_, "exported strands", e.counts, out.pointCounts.data(), total);
  std::vector<cl_uint> offsets(
      gpu::clh_lod_drawn_total_at(static_cast<gpu::clh_u32>(data_.bundles.size())) + 1);
  readBack(dev_, "strand offsets", inst->offsets, offsets.data(), offsets.size());
  // the root sample of each strand, for its uv (clh_strand_setup in hair_style.h)
  std::vector<glm::vec2> rootsQuad(roots_->size), rootsTri(roots_->size);
  readBack(dev_, "root sample set", roots_->quad, rootsQuad.data(), rootsQuad.size());
  readBack(dev_, "root sample set", roots_->triangle, rootsTri.data(), rootsTri.size());
  out.bundleOf.resize(total);
  out.uv.resize(2 * static_cast<std::size_t>(total));
  for (std::size_t b = 0; b + 1 < offsets.size(); ++b)
    for (cl_uint i = offsets[b]; i < offsets[b + 1] && i < total; ++i) {
      out.bundleOf[i] = static_cast<std::uint32_t>(b);
      const gpu::ClhBundle& bundle = data_.bundles[b];
      const std::uint32_t root = std::min<std::uint32_t>(i - offsets[b], roots_->size - 1);
      const glm::vec2 st = bundle.triangle ? rootsTri[root] : rootsQuad[root];
      const float w0 = (1.0f - st.x) * (1.0f - st.y), w1 = st.x * (1.0f - st.y), w2 = st.x * st.y,
                  w3 = (1.0f - st.x) * st.y;
      for (int c = 0; c < 2; ++c)
        out.uv[2 * i + c] = w0 * bundle.uv[c] + w1 * bundle.uv[2 + c] + w2 * bundle.uv[4 + c] +
                            w3 * bundle.uv[6 + c];
    }
  for (std::uint32_t s = 0; s < total; ++s) {
    const std::size_t base = static_cast<std::size_t>(s) * CLH_MAX_CONTROL_POINTS;
    for (std::uint32_t k = 0; k < out.pointCounts[s] && k < CLH_MAX_CONTROL_POINTS; ++k) {
      const cl_float4& q = p[base + k];
      const cl_float4& tq = t[base + k];
      out.points.insert(out.points.end(), {q.s[0], q.s[1], q.s[2]});
      out.tangents.insert(out.tangents.end(), {tq.s[0], tq.s[1], tq.s[2]});
      out.w.push_back(q.s[3]);
      out.ao.push_back(tq.s[3]);
    }
  }
  return out;
}

}  // namespace clhair
