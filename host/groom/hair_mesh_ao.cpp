// hair_mesh_ao.cpp — a hair mesh's ambient occlusion baked per layer vertex on the device
// (HairMeshGpu::bakeAo, hair_mesh_gpu.h), cached on disk by everything it depends on, and the
// sample the bake's tests compare with the CPU.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "cl/buffers.h"
#include "groom/hair_mesh_gpu.h"
#include "stages/ao_stage.h"

namespace clhair {

namespace {

// Bump when the host side of the bake below changes what it computes.
constexpr const char* kAoBakeVersion = "ao-bake-1";

template <typename T>
void appendBytes(std::string& out, const T* p, std::size_t n) {
  out.append(reinterpret_cast<const char*>(p), n * sizeof(T));
}

}  // namespace

// A cache entry of the bake or the extent: the device, the two programs the bake runs
// (expanded sources and build options), and every table and parameter of the sampled groom
// its strands come from.
std::string HairMeshGpu::aoCacheKey(const HairMesh& mesh, const char* what,
                                    const std::string& version) const {
  Device::Impl& dev = stages_.dev;
  std::string in = kAoBakeVersion;
  in += '|' + version;
  in += '|' + dev.buildOptions(dev.info.backend, "") + '|';
  in += dev.sources.program("strands.cl");
  in += dev.sources.program("ao.cl");
  appendBytes(in, data_.vertices.data(), data_.vertices.size());
  appendBytes(in, data_.bundles.data(), data_.bundles.size());
  appendBytes(in, &base_, 1);
  const std::int64_t counts[2] = {mesh.strandCount, mesh.controlPoints};
  appendBytes(in, counts, 2);
  appendBytes(in, &mesh.appearance.strandWidth, 1);
  return BinaryCache::dataKey(what, dev.info.platformName, dev.info.name, dev.info.driverVersion,
                              in);
}

// AO per layer vertex (kernels/ao.cl): a sample of the groom's strands fills a density
// grid of fibre extinction, then every vertex averages the visibility of 64 directions.
// The result depends only on the device and the cache key's inputs, so it is kept with the
// compiled programs: loading the same groom again skips the bake.
std::vector<float> HairMeshGpu::bakeAo(const HairMesh& mesh, GroomStages& stages) {
  constexpr std::int64_t kSampleStrands = 20000;
  constexpr int kGrid = 64;
  auto sample = std::make_shared<HairMesh>(mesh);
  sample->strandCount = std::min<std::int64_t>(mesh.strandCount, kSampleStrands);
  sample->controlPoints = std::min(mesh.controlPoints, 33);
  HairMeshGpu g(sample, stages, false);
  const std::size_t vertexTotal = g.data_.vertices.size();
  std::vector<float> ao(vertexTotal, 1.0f);
  if (sample->strandCount == 0) return ao;
  const BinaryCache& cache = stages.dev.binaries;
  const std::string key = cache.enabled() ? g.aoCacheKey(mesh, "ao") : std::string();
  if (cache.enabled()) {
    if (auto bytes = cache.load(key); bytes && bytes->size() == vertexTotal * sizeof(float)) {
      std::memcpy(ao.data(), bytes->data(), bytes->size());
      // an entry that is not a bake (damaged on disk) is baked again
      if (std::all_of(ao.begin(), ao.end(), [](float a) { return a >= 0.0f && a <= 1.0f; }))
        return ao;
      std::fill(ao.begin(), ao.end(), 1.0f);
    }
  }
  ao = g.bakeSample(mesh, kGrid);
  if (cache.enabled() && ao.size() == vertexTotal) {
    std::vector<unsigned char> bytes(ao.size() * sizeof(float));
    std::memcpy(bytes.data(), ao.data(), bytes.size());
    cache.store(key, bytes);
  }
  return ao;
}

// The bake itself, on this groom (the sample of `mesh`'s strands).
std::vector<float> HairMeshGpu::bakeSample(const HairMesh& mesh, int gridCells) {
  const std::size_t vertexTotal = data_.vertices.size();
  std::vector<float> ao(vertexTotal, 1.0f);
  std::unique_ptr<GroomInstanceGpu> inst = makeInstance();
  Exported e = exportOnDevice(*inst, 1.0f);
  if (e.total == 0) return ao;
  const glm::vec3 lo = data_.boundsMin, hi = data_.boundsMax;
  const float voxel = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) / gridCells * 1.02f;
  AoStage::Grid grid;
  grid.dims = {{static_cast<cl_uint>(std::ceil((hi.x - lo.x) / voxel)) + 1,
                static_cast<cl_uint>(std::ceil((hi.y - lo.y) / voxel)) + 1,
                static_cast<cl_uint>(std::ceil((hi.z - lo.z) / voxel)) + 1, 0}};
  grid.lo = {{lo.x, lo.y, lo.z, voxel}};
  // each sampled strand stands for total / sampled strands of the real groom
  const float represented =
      static_cast<float>(mesh.strandCount) / static_cast<float>(mesh_->strandCount);
  grid.scale = mesh.appearance.strandWidth * represented / (voxel * voxel * voxel);
  AoStage::Strands strands;
  strands.points = &e.points;
  strands.counts = &e.counts;
  strands.total = e.total;
  AoStage::Mesh target;
  target.vertices = &vertices_;
  target.bundles = &bundles_;
  target.vertexTotal = static_cast<std::uint32_t>(vertexTotal);
  target.bundleCount = static_cast<std::uint32_t>(data_.bundles.size());
  target.rootVertices = static_cast<std::uint32_t>(mesh.vertexCount);
  return stages_.ao.bake(strands, grid, target);
}

std::pair<glm::vec3, glm::vec3> HairMeshGpu::hairExtent(const HairMesh& mesh, GroomStages& stages) {
  constexpr std::int64_t kSampleStrands = 200000;
  constexpr float kWiden = 0.02f;  // of a sample's diagonal, on every side
  std::pair<glm::vec3, glm::vec3> box{glm::vec3(1.0f), glm::vec3(-1.0f)};
  auto sample = std::make_shared<HairMesh>(mesh);
  sample->strandCount = std::min<std::int64_t>(mesh.strandCount, kSampleStrands);
  if (sample->strandCount <= 0) return box;
  HairMeshGpu g(sample, stages, false);
  const BinaryCache& cache = stages.dev.binaries;
  // (the version names what the box is, from the constants above: bump "extent-2" when the
  // measure itself changes)
  const std::string version = "extent-2|" + std::to_string(kSampleStrands) + "|" +
                              std::to_string(static_cast<int>(std::lround(kWiden * 1000.0f)));
  const std::string key = cache.enabled() ? g.aoCacheKey(mesh, "extent", version) : std::string();
  float v[6];
  if (cache.enabled())
    if (auto bytes = cache.load(key); bytes && bytes->size() == sizeof(v)) {
      std::memcpy(v, bytes->data(), sizeof(v));
      // an entry that is not a box (damaged on disk) is measured again
      if (std::all_of(v, v + 6, [](float x) { return std::isfinite(x); }) && v[0] <= v[3] &&
          v[1] <= v[4] && v[2] <= v[5])
        return {glm::vec3(v[0], v[1], v[2]), glm::vec3(v[3], v[4], v[5])};
    }
  // the points alone (export's tangents, uv and bundles are not needed for a box)
  std::unique_ptr<GroomInstanceGpu> inst = g.makeInstance();
  const Exported e = g.exportOnDevice(*inst, 1.0f);
  const std::size_t slots = static_cast<std::size_t>(e.total) * CLH_MAX_CONTROL_POINTS;
  std::vector<cl_float4> points(slots);
  std::vector<cl_uint> counts(e.total);
  if (e.total > 0) {
    readBack(g.dev_, "exported strands", e.points, points.data(), slots);
    readBack(g.dev_, "exported strands", e.counts, counts.data(), e.total);
  }
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (std::size_t s = 0; s < counts.size(); ++s)
    for (cl_uint k = 0; k < counts[s] && k < CLH_MAX_CONTROL_POINTS; ++k) {
      const cl_float4& q = points[s * CLH_MAX_CONTROL_POINTS + k];
      const glm::vec3 p(q.s[0], q.s[1], q.s[2]);
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
  if (!(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z)) return box;
  const bool sampled = sample->strandCount < mesh.strandCount;
  const glm::vec3 widen(sampled ? kWiden * glm::length(hi - lo) : 0.0f);
  box = {lo - widen, hi + widen};
  if (cache.enabled()) {
    const float out[6] = {box.first.x,  box.first.y,  box.first.z,
                          box.second.x, box.second.y, box.second.z};
    std::vector<unsigned char> bytes(sizeof(out));
    std::memcpy(bytes.data(), out, sizeof(out));
    cache.store(key, bytes);
  }
  return box;
}

}  // namespace clhair
