// ao_field.cpp — see ao_field.h.
#include "groom/ao_field.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "cl/binary_cache.h"
#include "cl/buffers.h"
#include "cl/device_impl.h"

namespace clhair {

namespace {

constexpr float kAoFixed = 4096.0f;  // kernels/ao.cl, AO_FIXED
// Bump when the host side of the field changes what it computes.
constexpr const char* kAoFieldVersion = "ao-field-1";

}  // namespace

AoDensity splatAoDensity(const ExplicitData& d, float width, float represented) {
  AoDensity out;
  const glm::vec3 lo = d.boundsMin, hi = d.boundsMax;
  const float side = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  if (!(side > 0.0f) || d.strandOffsets.size() < 2) return out;
  const double segments = double(d.totalPoints) - double(d.strandOffsets.size() - 1);
  const int cells = std::clamp(static_cast<int>(std::cbrt(std::max(segments, 0.0) / 8.0)),
                               kAoFieldMinCells, kAoFieldMaxCells);
  const float voxel = side / static_cast<float>(cells) * 1.02f;
  cl_uint dims[3];
  for (int a = 0; a < 3; ++a)
    dims[a] = static_cast<cl_uint>(std::ceil((hi[a] - lo[a]) / voxel)) + 3;  // + margins
  out.grid.lo = {{lo.x - voxel, lo.y - voxel, lo.z - voxel, voxel}};
  out.grid.dims = {{dims[0], dims[1], dims[2], 0}};
  std::vector<double> sum(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2], 0.0);
  const bool look = d.fileLook.size() == d.points.size();
  const float perUnit = represented / (voxel * voxel * voxel);
  for (std::size_t s = 0; s + 1 < d.strandOffsets.size(); ++s)
    for (std::uint32_t k = d.strandOffsets[s]; k + 1 < d.strandOffsets[s + 1]; ++k) {
      const glm::vec3 a(d.points[k]), b(d.points[k + 1]);
      // the segment's diameter: the file's thickness (times its opacity), or the groom's
      // width times the file's opacity (fileLook.w = -opacity), or the groom's width
      float w = width;
      if (look && d.fileThickness) w = 0.5f * (d.fileLook[k].w + d.fileLook[k + 1].w);
      if (look && !d.fileThickness && d.fileOpacity)
        w = width * std::max(0.0f, -0.5f * (d.fileLook[k].w + d.fileLook[k + 1].w));
      // in pieces of at most half a voxel, each at its midpoint
      const float len = glm::length(b - a);
      const int pieces = std::clamp(static_cast<int>(std::ceil(2.0f * len / voxel)), 1, 4096);
      for (int q = 0; q < pieces; ++q) {
        const glm::vec3 m = a + (b - a) * ((float(q) + 0.5f) / float(pieces));
        int v[3];
        bool inside = true;
        for (int ax = 0; ax < 3; ++ax) {
          v[ax] = static_cast<int>(std::floor((m[ax] - out.grid.lo.s[ax]) / voxel));
          inside = inside && v[ax] >= 0 && v[ax] < static_cast<int>(dims[ax]);
        }
        if (inside)
          sum[(std::size_t(v[2]) * dims[1] + v[1]) * dims[0] + v[0]] +=
              double(len) / pieces * w * perUnit;
      }
    }
  out.density.resize(sum.size());
  for (std::size_t i = 0; i < sum.size(); ++i)
    out.density[i] = static_cast<std::uint32_t>(std::min(sum[i] * kAoFixed + 0.5, 4.0e9));
  return out;
}

AoDensity withOccluders(const AoDensity& d, const Scene& scene, const glm::mat4& objToWorld) {
  AoDensity out = d;
  if (d.density.empty()) return out;
  const cl_uint nx = d.grid.dims.s[0], ny = d.grid.dims.s[1], nz = d.grid.dims.s[2];
  const float voxel = d.grid.lo.s[3];
  const glm::vec3 lo(d.grid.lo.s[0], d.grid.lo.s[1], d.grid.lo.s[2]);
  // an opaque voxel: a half-voxel step through it is 16 optical depths
  const auto solid = static_cast<std::uint32_t>(std::min(32.0 / voxel * kAoFixed, 4.0e9));
  auto mark = [&](glm::vec3 objPoint) {
    const glm::vec3 c = (objPoint - lo) / voxel;
    if (!(c.x >= 0.0f && c.y >= 0.0f && c.z >= 0.0f && c.x < nx && c.y < ny && c.z < nz)) return;
    out.density[(std::size_t(c.z) * ny + std::size_t(c.y)) * nx + std::size_t(c.x)] = solid;
  };
  // spheres: every voxel whose centre is inside
  for (const Sphere& sp : scene.spheres)
    for (cl_uint z = 0; z < nz; ++z)
      for (cl_uint y = 0; y < ny; ++y)
        for (cl_uint x = 0; x < nx; ++x) {
          const glm::vec3 p = lo + (glm::vec3(x, y, z) + 0.5f) * voxel;
          const glm::vec3 w(objToWorld * glm::vec4(p, 1.0f));
          if (glm::length(w - sp.center) < sp.radius) mark(p);
        }
  // meshes: their surfaces, sampled at a third of a voxel (a shell the march cannot step over)
  const glm::mat4 worldToObj = glm::inverse(objToWorld);
  for (const MeshInstance& mi : scene.meshes) {
    if (!mi.mesh) continue;
    const glm::mat4 m = worldToObj * mi.transform;
    const std::vector<glm::vec3>& pos = mi.mesh->positions;
    for (std::size_t t = 0; t + 2 < mi.mesh->indices.size(); t += 3) {
      const glm::vec3 a(m * glm::vec4(pos[mi.mesh->indices[t]], 1.0f));
      const glm::vec3 b(m * glm::vec4(pos[mi.mesh->indices[t + 1]], 1.0f));
      const glm::vec3 c(m * glm::vec4(pos[mi.mesh->indices[t + 2]], 1.0f));
      const float edge = std::max({glm::length(b - a), glm::length(c - a), glm::length(c - b)});
      if (!std::isfinite(edge)) continue;
      // (bounded before the conversion: a mesh far larger than the grid)
      const int n = 1 + static_cast<int>(std::min(255.0f, std::ceil(3.0f * edge / voxel)));
      for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j)
          mark(a + (b - a) * (float(i) / n) + (c - a) * (float(j) / n));
    }
  }
  return out;
}

AoField bakeAoField(Device::Impl& dev, AoStage& stage, const AoDensity& density) {
  AoField f;
  f.lo = density.grid.lo;
  f.dims = density.grid.dims;
  const std::size_t cells = f.voxels();
  std::vector<float> ao;
  const BinaryCache& cache = dev.binaries;
  std::string key;
  if (cache.enabled()) {
    std::string in = kAoFieldVersion;
    in += '|' + dev.buildOptions(dev.info.backend, "") + '|' + dev.sources.program("ao.cl");
    in.append(reinterpret_cast<const char*>(&f.lo), sizeof(f.lo));
    in.append(reinterpret_cast<const char*>(&f.dims), sizeof(f.dims));
    in.append(reinterpret_cast<const char*>(density.density.data()),
              density.density.size() * sizeof(std::uint32_t));
    key = BinaryCache::dataKey("aofield", dev.info.platformName, dev.info.name,
                               dev.info.driverVersion, in);
    if (auto bytes = cache.load(key); bytes && bytes->size() == cells * sizeof(float)) {
      ao.resize(cells);
      std::memcpy(ao.data(), bytes->data(), bytes->size());
      // an entry that is not a field (damaged on disk) is baked again
      if (!std::all_of(ao.begin(), ao.end(), [](float a) { return a >= 0.0f && a <= 1.0f; }))
        ao.clear();
    }
  }
  if (ao.empty()) {
    ao = stage.field(density.density, density.grid);
    if (cache.enabled()) {
      std::vector<unsigned char> bytes(ao.size() * sizeof(float));
      std::memcpy(bytes.data(), ao.data(), bytes.size());
      cache.store(key, bytes);
    }
  }
  f.values = makeBuffer<cl_float>(dev, "the AO field", cells, ao.data());
  f.host = std::move(ao);
  return f;
}

}  // namespace clhair
