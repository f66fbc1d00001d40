// renderer.cpp — the frame loop: opaque scene, then per groom lod -> scan -> strands ->
// shade -> composite, over one render target; plus strand export.
//
// A groom is a hair mesh (strands generated per frame, kernels/strands.cl) or explicit
// strands (a StrandGroom, kernels/strands_explicit.cl); both fill the same G-buffer and
// share shading, filter and compositing. Device resources of a groom (hair-mesh records
// or strand tables, LOD and scan buffers) are uploaded once per mesh or StrandGroom and
// kept while the Renderer lives; target-sized buffers are reallocated only when the
// resolution changes. Every size is checked against the device's maximum allocation
// before anything is created.
#include "clhair/renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <sstream>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include "cl/cl_error.h"
#include "cl/device_impl.h"
#include "groom/blue_noise.h"
#include "groom/explicit_data.h"
#include "groom/groom_data.h"
#include "clhair/lod_math.h"
#include "stages/composite_stage.h"
#include "stages/dispatch.h"
#include "stages/explicit_stage.h"
#include "stages/filter_stage.h"
#include "stages/shadow_stage.h"
#include "lighting/environment.h"
#include "stages/lod_stage.h"
#include "stages/mesh_stage.h"
#include "stages/opaque_stage.h"
#include "stages/shade_stage.h"
#include "stages/strand_stage.h"

namespace clhair {

namespace {

constexpr std::uint32_t kMinRootSet = 1024;
constexpr std::uint32_t kMaxRootSet = 1u << 16;

void store4(float* dst, const glm::vec3& v, float w) {
  dst[0] = v.x;
  dst[1] = v.y;
  dst[2] = v.z;
  dst[3] = w;
}

// Row-major 3x4 from the upper 3x4 of a column-major glm matrix.
void storeMat34(float* dst, const glm::mat4& m) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) dst[r * 4 + c] = m[c][r];
}

glm::mat4 worldToView(const Camera& cam) {
  glm::vec3 f = glm::normalize(cam.target - cam.position);
  glm::vec3 r = glm::normalize(glm::cross(f, cam.up));
  glm::vec3 u = glm::cross(r, f);
  glm::mat4 m(1.0f);
  for (int c = 0; c < 3; ++c) {
    m[c][0] = r[c];
    m[c][1] = u[c];
    m[c][2] = f[c];
  }
  m[3][0] = -glm::dot(r, cam.position);
  m[3][1] = -glm::dot(u, cam.position);
  m[3][2] = -glm::dot(f, cam.position);
  return m;
}

gpu::ClhViewGpu makeView(const Camera& cam, int width, int height) {
  gpu::ClhViewGpu v;
  std::memset(&v, 0, sizeof(v));
  glm::mat4 w2v = worldToView(cam);
  storeMat34(v.world_to_view, w2v);
  storeMat34(v.view_to_world, glm::inverse(w2v));
  float fy = 0.5f * static_cast<float>(height) / std::tan(glm::radians(cam.fovYDegrees) * 0.5f);
  v.fx = fy;
  v.fy = fy;
  v.cx = 0.5f * static_cast<float>(width);
  v.cy = 0.5f * static_cast<float>(height);
  v.width = static_cast<gpu::clh_u32>(width);
  v.height = static_cast<gpu::clh_u32>(height);
  v.samples = 1;
  store4(v.eye, cam.position, 1.0f);
  return v;
}

template <typename T>
cl::Buffer makeBuffer(Device::Impl& dev, const std::string& what, std::size_t count,
                      const T* data = nullptr) {
  std::size_t bytes = std::max<std::size_t>(count, 1) * sizeof(T);
  if (bytes > dev.info.maxAlloc)
    throw Error(what + " needs " + std::to_string(bytes >> 20) + " MiB in one buffer but " +
                dev.info.name + " allows at most " + std::to_string(dev.info.maxAlloc >> 20) + " MiB");
  return clCall("allocating " + what, [&] {
    cl::Buffer b(dev.context, CL_MEM_READ_WRITE, bytes);
    if (data && count > 0) dev.queue.enqueueWriteBuffer(b, CL_TRUE, 0, count * sizeof(T), data);
    return b;
  });
}

template <typename T>
void upload(Device::Impl& dev, cl::Buffer& buffer, const T* data, std::size_t count) {
  if (count == 0) return;
  clCall("uploading", [&] {
    dev.queue.enqueueWriteBuffer(buffer, CL_TRUE, 0, count * sizeof(T), data);
    return 0;
  });
}

struct GroomResources {
  std::shared_ptr<const HairMesh> keepAlive;
  GroomData data;
  std::vector<float> ao;     // baked or given AO per layer vertex
  bool aoUploaded = true;    // the vertex buffer holds `ao` (else AO = 1)
  gpu::ClhGroomGpu params;
  cl::Buffer vertices, bundles, groom, lod, counts, offsets;
};

// An explicit groom on the device: strand tables in LOD order (explicit_data.h) plus the
// per-chunk LOD records and their scan. The host keeps everything but the points.
struct ExplicitResources {
  std::shared_ptr<const StrandGroom> keepAlive;
  ExplicitData data;
  gpu::ClhGroomGpu params;
  cl::Buffer points, strandOffsets, uv, chunks, chunkBounds, groom, lod, counts, offsets;
};

std::uint64_t bufferBytes(const cl::Buffer& b) {
  if (!b()) return 0;
  return clCall("reading a buffer size", [&] { return static_cast<std::uint64_t>(b.getInfo<CL_MEM_SIZE>()); });
}

// Depth range of the view-space box of object bounds [lo, hi]; false when all of it lies
// behind the camera.
bool depthRange(const glm::vec3& lo, const glm::vec3& hi, const glm::mat4& o2v, float& nearZ, float& farZ) {
  float zmin = 1e30f, zmax = -1e30f;
  for (int c = 0; c < 8; ++c) {
    glm::vec3 corner((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
    float z = (o2v * glm::vec4(corner, 1.0f)).z;
    zmin = std::min(zmin, z);
    zmax = std::max(zmax, z);
  }
  if (zmax <= 1e-4f) return false;
  nearZ = std::max(zmin, 1e-4f);
  farZ = std::max(zmax, nearZ * 1.0001f + 1e-6f);
  return true;
}

}  // namespace

const char* dispatchModeName(DispatchMode m) {
  switch (m) {
    case DispatchMode::Auto:
      return "auto";
    case DispatchMode::ReadBack:
      return "readback";
    case DispatchMode::OverLaunch:
      return "overlaunch";
    case DispatchMode::Persistent:
      return "persistent";
  }
  return "?";
}

DispatchMode parseDispatchMode(const std::string& name) {
  for (DispatchMode m : {DispatchMode::Auto, DispatchMode::ReadBack, DispatchMode::OverLaunch, DispatchMode::Persistent})
    if (name == dispatchModeName(m)) return m;
  throw Error("unknown dispatch mode \"" + name + "\"; expected auto, readback, overlaunch or persistent");
}

double Frame::stageMs(const std::string& stage) const {
  for (const StageTime& t : timings)
    if (t.stage == stage) return t.ms;
  return 0.0;
}

double Frame::totalMs() const {
  double s = 0.0;
  for (const StageTime& t : timings) s += t.ms;
  return s;
}

struct Renderer::Impl {
  Device device;
  Device::Impl& dev;
  OpaqueStage opaque;
  MeshStage meshStage;
  LodStage lod;
  StrandStage strands;
  ShadeStage shade;
  FilterStage filter;
  ShadowStage shadow;
  CompositeStage composite;
  ExplicitStage explicitStage;
  cl::Kernel clear;
  Profiler profiler;

  std::map<const HairMesh*, std::unique_ptr<GroomResources>> grooms;
  std::map<const StrandGroom*, std::unique_ptr<ExplicitResources>> explicitGrooms;
  bool trueWidthOnly = false;  // reference passes: explicit grooms ignore their minimum hit diameter
  RootSets roots;
  cl::Buffer rootsQuad, rootsTri;

  int width = 0, height = 0, layers = 0;
  cl::Buffer color, depth, gbuffer, hair, filtered, stats, filterParams;
  cl::Buffer view, scene, spheres, planes, lights;
  // the scene's triangle meshes in world space, rebuilt when the scene's meshes change
  cl::Buffer meshVertices, meshNormals, meshTriangles, meshColors, meshWords;
  std::uint32_t meshVertexCount = 0, meshTriangleCount = 0, meshColorCount = 0;
  std::vector<MeshInstance> uploadedMeshes;
  // deep opacity maps: one ClhShadowGpu per slot and the shared texel buffers
  int shadowRes = 0;
  std::array<cl::Buffer, CLH_MAX_SHADOWS> shadowOne;
  cl::Buffer shadowAll, shadowOpaque, shadowHair, shadowOpacity;
  cl::Buffer lightView, lightColor, lightDepth, lightGBuffer, exportView;

  explicit Impl(Device d)
      : device(std::move(d)),
        dev(*device.impl()),
        opaque(dev),
        meshStage(dev),
        lod(dev),
        strands(dev),
        shade(dev),
        filter(dev),
        shadow(dev),
        composite(dev),
        explicitStage(dev),
        clear(dev.kernel("clear.cl", "clear_words")) {
    view = makeBuffer<gpu::ClhViewGpu>(dev, "view parameters", 1);
    lightView = makeBuffer<gpu::ClhViewGpu>(dev, "light view parameters", 1);
    exportView = makeBuffer<gpu::ClhViewGpu>(dev, "export view parameters", 1);
    shadowAll = makeBuffer<gpu::ClhShadowGpu>(dev, "shadow parameters", CLH_MAX_SHADOWS);
    for (auto& b : shadowOne) b = makeBuffer<gpu::ClhShadowGpu>(dev, "shadow parameters", 1);
    filterParams = makeBuffer<gpu::ClhFilterGpu>(dev, "filter parameters", 1);
    scene = makeBuffer<gpu::ClhSceneGpu>(dev, "scene parameters", 1);
  }

  void ensureRoots(std::uint32_t needed) {
    std::uint32_t size = kMinRootSet;
    while (size < needed && size < kMaxRootSet) size <<= 1;
    if (needed > kMaxRootSet)
      throw Error("a bundle requests " + std::to_string(needed) + " strands; at most " +
                  std::to_string(kMaxRootSet) + " per bundle are supported (split its scalp face)");
    if (roots.size() >= size) return;
    roots = makeRootSets(size);
    rootsQuad = makeBuffer<glm::vec2>(dev, "root sample set", roots.quad.size(), roots.quad.data());
    rootsTri = makeBuffer<glm::vec2>(dev, "root sample set", roots.triangle.size(), roots.triangle.data());
  }

  // Device resources of a groom; AO is baked on the device when the mesh has none.
  std::unique_ptr<GroomResources> buildGroom(const HairMesh& mesh, bool bake = true) {
    auto g = std::make_unique<GroomResources>();
    g->data = prepareGroom(mesh);
    if (bake && mesh.ao.empty()) {
      std::vector<float> ao = bakeAo(mesh);
      for (std::size_t i = 0; i < ao.size() && i < g->data.vertices.size(); ++i) g->data.vertices[i].tan[3] = ao[i];
    }
    g->ao.resize(g->data.vertices.size());
    for (std::size_t i = 0; i < g->ao.size(); ++i) g->ao[i] = g->data.vertices[i].tan[3];
    std::memset(&g->params, 0, sizeof(g->params));
    fillGroomParams(mesh, g->data, g->params);
    ensureRoots(g->data.maxBundleStrands);
    g->params.root_set_size = roots.size();
    const std::string what = "groom \"" + mesh.name + "\"";
    g->vertices = makeBuffer(dev, what + " hair-mesh vertices", g->data.vertices.size(), g->data.vertices.data());
    g->bundles = makeBuffer(dev, what + " bundles", g->data.bundles.size(), g->data.bundles.data());
    g->groom = makeBuffer<gpu::ClhGroomGpu>(dev, what + " parameters", 1, &g->params);
    g->lod = makeBuffer<cl_uint4>(dev, what + " LOD records", g->data.bundles.size());
    g->counts = makeBuffer<cl_uint>(dev, what + " strand counts", 2 * g->data.bundles.size());
    g->offsets = makeBuffer<cl_uint>(dev, what + " strand offsets", g->data.bundles.size() + 2);
    return g;
  }

  struct Exported {
    std::uint32_t total = 0;
    cl::Buffer points, tangents, counts;  // CLH_MAX_CONTROL_POINTS slots per strand
  };

  // Runs strands_export over a groom: lod = 1 full detail (the LOD pass with LOD off and an
  // unbounded reach keeps every bundle), lod < 1 every bundle at that LOD value.
  Exported exportStrands(GroomResources& g, const HairMesh& mesh, float lod) {
    g.params.lod_enabled = 0;
    upload(dev, g.groom, &g.params, 1);
    Exported e;
    if (lod >= 1.0f) {
      // its own view buffer: a bake may run in the middle of a frame
      gpu::ClhViewGpu v = makeView(Camera{}, 1, 1);
      upload(dev, exportView, &v, 1);
      LodStage::Params lp = lodParams(g, 1e30f, exportView);
      this->lod.enqueue(lp, nullptr);
      e.total = this->lod.readTotal(lp);
      if (e.total != g.data.totalStrands)
        throw Error("strand export: the LOD pass kept " + std::to_string(e.total) + " of " +
                    std::to_string(g.data.totalStrands) + " strands");
    } else {
      // the records the LOD pass would write, computed here
      const std::size_t B = g.data.bundles.size();
      std::vector<cl_uint4> records(B);
      std::vector<cl_uint> offsets(B + 1, 0);
      const auto layers = static_cast<gpu::clh_u32>(mesh.layerCount);
      const gpu::clh_u32 cmax = fullDetailControlPoints(mesh);
      const float gamma = gpu::clh_lod_morph(lod, layers, cmax, mesh.lod.morphWindow);
      std::uint32_t gammaBits, lodBits;
      std::memcpy(&gammaBits, &gamma, 4);
      std::memcpy(&lodBits, &lod, 4);
      for (std::size_t b = 0; b < B; ++b) {
        const gpu::ClhBundle& bundle = g.data.bundles[b];
        gpu::clh_u32 n = gpu::clh_lod_strands(lod, bundle.strand_count, bundle.lod_delta);
        records[b] = {{n, gpu::clh_lod_control_points(lod, layers, cmax), lodBits, gammaBits}};
        offsets[b + 1] = offsets[b] + n;
      }
      e.total = offsets[B];
      upload(dev, g.lod, records.data(), B);
      upload(dev, g.offsets, offsets.data(), B + 1);
    }
    if (e.total == 0) return e;
    const std::size_t slots = static_cast<std::size_t>(e.total) * CLH_MAX_CONTROL_POINTS;
    e.points = makeBuffer<cl_float4>(dev, "exported strand points", slots);
    e.tangents = makeBuffer<cl_float4>(dev, "exported strand tangents", slots);
    e.counts = makeBuffer<cl_uint>(dev, "exported strand point counts", e.total);
    strands.exportStrands(strandInputs(g), e.total, e.points, e.tangents, e.counts, nullptr);
    return e;
  }

  // AO per layer vertex (kernels/ao.cl): a sample of the groom's strands fills a density
  // grid of fibre extinction, then every vertex averages the visibility of 64 directions.
  std::vector<float> bakeAo(const HairMesh& mesh) {
    constexpr std::int64_t kSampleStrands = 20000;
    constexpr int kGrid = 64;
    HairMesh sample = mesh;
    sample.strandCount = std::min<std::int64_t>(mesh.strandCount, kSampleStrands);
    sample.controlPoints = std::min(mesh.controlPoints, 33);
    auto g = buildGroom(sample, false);
    const std::size_t vertexTotal = g->data.vertices.size();
    std::vector<float> ao(vertexTotal, 1.0f);
    if (sample.strandCount == 0) return ao;
    Exported e = exportStrands(*g, sample, 1.0f);
    const glm::vec3 lo = g->data.boundsMin, hi = g->data.boundsMax;
    const float voxel = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) / kGrid * 1.02f;
    cl_uint4 dims{{static_cast<cl_uint>(std::ceil((hi.x - lo.x) / voxel)) + 1, static_cast<cl_uint>(std::ceil((hi.y - lo.y) / voxel)) + 1,
                   static_cast<cl_uint>(std::ceil((hi.z - lo.z) / voxel)) + 1, 0}};
    const std::size_t cells = static_cast<std::size_t>(dims.s[0]) * dims.s[1] * dims.s[2];
    cl_float4 gridLo{{lo.x, lo.y, lo.z, voxel}};
    // each sampled strand stands for total / sampled strands of the real groom
    const float represented = static_cast<float>(mesh.strandCount) / static_cast<float>(sample.strandCount);
    const float scale = mesh.appearance.strandWidth * represented / (voxel * voxel * voxel);
    cl::Buffer density = makeBuffer<cl_uint>(dev, "the AO density grid", cells);
    cl::Buffer out = makeBuffer<cl_float>(dev, "baked AO", vertexTotal);
    clCall("baking ambient occlusion", [&] {
      cl::Kernel clearGrid = dev.kernel("ao.cl", "ao_clear");
      clearGrid.setArg(0, density);
      clearGrid.setArg(1, static_cast<cl_uint>(cells));
      dispatch(dev, clearGrid, "ao", cl::NDRange(cells), cl::NDRange(64), nullptr);
      cl::Kernel vox = dev.kernel("ao.cl", "ao_voxelize");
      vox.setArg(0, e.points);
      vox.setArg(1, e.counts);
      vox.setArg(2, e.total);
      vox.setArg(3, gridLo);
      vox.setArg(4, dims);
      vox.setArg(5, scale);
      vox.setArg(6, density);
      dispatch(dev, vox, "ao", cl::NDRange(std::size_t(e.total) * CLH_MAX_CONTROL_POINTS), cl::NDRange(64), nullptr);
      cl::Kernel bake = dev.kernel("ao.cl", "ao_bake");
      bake.setArg(0, g->vertices);
      bake.setArg(1, static_cast<cl_uint>(vertexTotal));
      bake.setArg(2, g->bundles);
      bake.setArg(3, static_cast<cl_uint>(g->data.bundles.size()));
      bake.setArg(4, static_cast<cl_uint>(mesh.vertexCount));
      bake.setArg(5, gridLo);
      bake.setArg(6, dims);
      bake.setArg(7, density);
      bake.setArg(8, out);
      dispatch(dev, bake, "ao", cl::NDRange(vertexTotal), cl::NDRange(64), nullptr);
      dev.queue.enqueueReadBuffer(out, CL_TRUE, 0, vertexTotal * sizeof(float), ao.data());
      return 0;
    });
    return ao;
  }

  // Uploads the groom's vertices with its AO, or with AO = 1, as the frame asks.
  void applyAo(GroomResources& g, bool on) {
    if (g.aoUploaded == on) return;
    std::vector<gpu::ClhMeshVertex> v = g.data.vertices;
    for (std::size_t i = 0; i < v.size(); ++i) v[i].tan[3] = on ? g.ao[i] : 1.0f;
    upload(dev, g.vertices, v.data(), v.size());
    g.aoUploaded = on;
  }

  GroomResources& groomFor(const std::shared_ptr<const HairMesh>& mesh) {
    auto it = grooms.find(mesh.get());
    if (it != grooms.end()) return *it->second;
    auto g = buildGroom(*mesh);
    g->keepAlive = mesh;
    GroomResources& ref = *g;
    grooms[mesh.get()] = std::move(g);
    return ref;
  }

  void ensureTarget(int w, int h, int msaa) {
    if (w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide)
      throw Error("resolution " + std::to_string(w) + "x" + std::to_string(h) +
                  " is outside 1.." + std::to_string(kMaxImageSide) + " per side");
    if (msaa != 1 && msaa != 2 && msaa != 4 && msaa != 8)
      throw Error("MSAA must be 1, 2, 4 or 8 samples, not " + std::to_string(msaa));
    std::size_t n = static_cast<std::size_t>(w) * h;
    std::string res = std::to_string(w) + "x" + std::to_string(h);
    if (w != width || h != height) {
      color = makeBuffer<cl_float4>(dev, "the " + res + " colour target", n);
      depth = makeBuffer<cl_float>(dev, "the " + res + " depth target", n);
      hair = makeBuffer<cl_float4>(dev, "the " + res + " hair colour buffer", n);
      filtered = makeBuffer<cl_float4>(dev, "the " + res + " filtered hair buffer", n);
      layers = 0;
    }
    // sample layers plus the conservative layer
    if (layers != msaa + 1)
      gbuffer = makeBuffer<cl_ulong>(dev, "the " + res + " G-buffer with " + std::to_string(msaa + 1) + " layers",
                                     n * static_cast<std::size_t>(msaa + 1));
    if (!stats()) stats = makeBuffer<cl_uint>(dev, "raster statistics", 4);
    width = w;
    height = h;
    layers = msaa + 1;
  }

  void uploadFilter(const FilterParams& f) {
    if (f.radius < 0 || f.radius > 8) throw Error("filter radius " + std::to_string(f.radius) + " is outside 0..8");
    gpu::ClhFilterGpu g{};
    g.radius = static_cast<gpu::clh_u32>(f.radius);
    g.s_par = f.sPar;
    g.s_perp = f.sPerp;
    g.sigma_c = f.sigmaC;
    g.depth_reject = f.depthReject;
    g.depth_mismatch = f.depthMismatch;
    g.strip = f.strip;
    g.promote = f.promote ? 1u : 0u;
    upload(dev, filterParams, &g, 1);
  }

  void ensureShadowBuffers(int res) {
    if (res == shadowRes) return;
    const std::size_t plane = static_cast<std::size_t>(res) * res;
    const std::string what = std::to_string(res) + "x" + std::to_string(res) + " deep opacity maps";
    shadowOpaque = makeBuffer<cl_float>(dev, what, plane * CLH_MAX_SHADOWS);
    shadowHair = makeBuffer<cl_float>(dev, what, plane * CLH_MAX_SHADOWS);
    shadowOpacity = makeBuffer<cl_uint>(dev, what, plane * CLH_MAX_SHADOWS * CLH_DOM_LAYERS);
    lightColor = makeBuffer<cl_float4>(dev, what, plane);
    lightDepth = makeBuffer<cl_float>(dev, what, plane);
    lightGBuffer = makeBuffer<cl_ulong>(dev, what, plane * 2);
    shadowRes = res;
  }

  std::uint64_t shadowStrands = 0;  // drawn by the last renderShadows (FrameStats)

  // Everything the deep opacity maps depend on, to reuse them while it stays the same: the
  // bytes of the lights, shadow settings, opaque primitives, transforms and options, and
  // the identity of every groom and mesh (held, so an address is never reused).
  struct ShadowKey {
    std::vector<unsigned char> bytes;
    std::vector<std::shared_ptr<const void>> held;
    bool operator==(const ShadowKey& o) const { return bytes == o.bytes && held == o.held; }
  };
  ShadowKey lastShadowKey;
  bool shadowsValid = false;

  ShadowKey shadowKey(const Scene& s, const RenderOptions& o) const {
    ShadowKey k;
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
    }
    putValue(o.lod);
    putValue(o.shadowLod);
    putValue(o.lodLambdaScale);
    putValue(o.shadowLodCorrection);
    putValue(o.ambientOcclusion);
    putValue(trueWidthOnly);
    putValue(shadowCorrection);
    const std::size_t counts[4] = {s.lights.size(), s.spheres.size(), s.planes.size(), s.grooms.size()};
    putValue(counts);
    return k;
  }

  // Deep opacity maps of every shadowed light over all grooms (Yuksel & Keyser 2008), built
  // with the strand kernels from the light's view (with LOD). Must run before the opaque
  // pass, which receives hair shadows too.
  void renderShadows(const Scene& s, const RenderOptions& cameraOptions) {
    shadowStrands = 0;
    // the light's passes use LOD unless the caller turned it off explicitly
    RenderOptions options = cameraOptions;
    options.lod = cameraOptions.lod == 0 ? 0 : 1;
    if (cameraOptions.shadowLod >= 0) options.lod = cameraOptions.shadowLod;
    std::vector<gpu::ClhShadowGpu> params(CLH_MAX_SHADOWS);
    int slot = 0;
    for (const Light& light : s.lights) {
      if (!light.shadows || s.grooms.empty() || slot >= CLH_MAX_SHADOWS) continue;
      const int res = s.shadows.resolution;
      ensureShadowBuffers(res);
      const std::size_t plane = static_cast<std::size_t>(res) * res;
      // the light's view: a pinhole at the light (directional: far away, narrow) framing all grooms
      glm::vec3 lo(1e30f), hi(-1e30f);
      for (const GroomInstance& gi : s.grooms) {
        glm::vec3 blo, bhi;
        groomBounds(gi, blo, bhi);
        for (int c = 0; c < 8; ++c) {
          glm::vec3 corner((c & 1) ? bhi.x : blo.x, (c & 2) ? bhi.y : blo.y, (c & 4) ? bhi.z : blo.z);
          glm::vec3 w = glm::vec3(gi.transform * glm::vec4(corner, 1.0f));
          lo = glm::min(lo, w);
          hi = glm::max(hi, w);
        }
      }
      const glm::vec3 center = 0.5f * (lo + hi);
      const float radius = 0.5f * glm::length(hi - lo);
      Camera cam;
      cam.target = center;
      if (light.type == Light::Type::Point) {
        cam.position = light.position;
      } else {
        cam.position = center + glm::normalize(light.direction) * (radius * 20.0f);
      }
      float dist = glm::length(cam.position - center);
      if (dist < 1e-6f) {  // a light at the groom's center: no map, the slot stays unshadowed
        ++slot;
        continue;
      }
      glm::vec3 dir = (center - cam.position) / dist;
      cam.up = std::fabs(dir.y) > 0.95f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
      cam.fovYDegrees = std::min(150.0f, 2.0f * glm::degrees(std::atan(radius / std::max(dist - radius, radius * 0.05f))) * 1.05f);
      gpu::ClhViewGpu lv = makeView(cam, res, res);
      upload(dev, lightView, &lv, 1);
      const glm::mat4 w2v = worldToView(cam);
      const float nearZ = std::max(dist - radius, 1e-4f), farZ = dist + radius;

      gpu::ClhShadowGpu& sh = params[slot];
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
      sh.depth_near = nearZ;
      sh.depth_far = farZ;
      upload(dev, shadowOne[slot], &sh, 1);

      // the opaque scene from the light: its depth only
      opaque.enqueue({&scene, &lightView, &spheres, &planes, &lights, &shadowAll, &shadowOpaque, &shadowHair,
                      &shadowOpacity, &envTexels(), &envLevels(), &envSh(), &background, &lightColor, &lightDepth, res, res, false},
                     &profiler);
      drawMeshes(lightView, lightColor, lightDepth, res, res, false);  // meshes cast into the maps too
      clCall("copying the light's opaque depth", [&] {
        dev.queue.enqueueCopyBuffer(lightDepth, shadowOpaque, 0, plane * slot * sizeof(float), plane * sizeof(float));
        return 0;
      });
      // hair depth: the strand pass from the light into the light's G-buffer
      clearWords(lightGBuffer, plane * 2);
      // per drawn instance: its resources and drawn total. Instances of one mesh or strand
      // file share resources (parameters, LOD records), so a resource seen twice is
      // prepared again for each instance before its opacity pass.
      struct Pass {
        const GroomInstance* instance;
        GroomResources* mesh;
        ExplicitResources* explicitGroom;
        std::uint32_t total;
      };
      std::vector<Pass> passes;
      std::map<const void*, int> uses;
      for (const GroomInstance& gi : s.grooms) {
        if (gi.strands) {
          ExplicitResources& e = explicitFor(gi.strands);
          if (!prepareExplicitView(e, gi.transform, w2v, options, nearZ, farZ)) continue;
          const ExplicitStage::Inputs in = explicitInputs(e);
          explicitStage.lod(in, lightView, &profiler);
          const std::uint32_t total = explicitStage.readTotal(in);
          passes.push_back({&gi, nullptr, &e, total});
          shadowStrands += total;
          ++uses[&e];
          StrandStage::Raster rs{&lightView, &lightDepth, &lightGBuffer, &stats, 1, false, DispatchMode::ReadBack, total};
          explicitStage.raster(in, rs, &profiler);
          continue;
        }
        GroomResources& g = groomFor(gi.mesh);
        if (!prepareGroomView(g, gi.transform, w2v, options, nearZ, farZ)) continue;
        LodStage::Params lp = lodParams(g, viewReach(g, gi.transform), lightView);
        lod.enqueue(lp, &profiler);
        std::uint32_t total = lod.readTotal(lp);
        passes.push_back({&gi, &g, nullptr, total});
        shadowStrands += total;
        ++uses[&g];
        StrandStage::Raster rs{&lightView, &lightDepth, &lightGBuffer, &stats, 1, false, DispatchMode::ReadBack, total};
        strands.raster(strandInputs(g), rs, &profiler);
      }
      shadow.resolveDepth(shadowOne[slot], lightGBuffer, shadowHair, res, res, &profiler);
      shadow.clearOpacity(shadowOne[slot], shadowOpacity, plane, &profiler);
      for (Pass& p : passes) {
        if (p.explicitGroom) {
          const ExplicitStage::Inputs in = explicitInputs(*p.explicitGroom);
          if (uses[p.explicitGroom] > 1) {
            prepareExplicitView(*p.explicitGroom, p.instance->transform, w2v, options, nearZ, farZ);
            explicitStage.lod(in, lightView, &profiler);
            p.total = explicitStage.readTotal(in);
          }
          explicitStage.opacity(in, lightView, shadowOpaque, shadowOne[slot], shadowHair, shadowOpacity, p.total,
                                &profiler);
          continue;
        }
        if (uses[p.mesh] > 1) {
          prepareGroomView(*p.mesh, p.instance->transform, w2v, options, nearZ, farZ);
          LodStage::Params lp = lodParams(*p.mesh, viewReach(*p.mesh, p.instance->transform), lightView);
          lod.enqueue(lp, &profiler);
          p.total = lod.readTotal(lp);
        }
        shadow.opacity(strandInputs(*p.mesh), lightView, shadowOpaque, shadowOne[slot], shadowHair, shadowOpacity,
                       p.total, &profiler);
      }
      ++slot;
    }
    if (slot > 0) upload(dev, shadowAll, params.data(), CLH_MAX_SHADOWS);
    if (shadowRes == 0) ensureShadowBuffers(1);
  }

  void clearWords(cl::Buffer& buffer, std::size_t words) {
    clCall("clearing the G-buffer", [&] {
      clear.setArg(0, buffer);
      clear.setArg(1, ~cl_ulong(0));
      clear.setArg(2, static_cast<cl_ulong>(words));
      dispatch(dev, clear, "clear", cl::NDRange(words), cl::NDRange(256), &profiler);
      return 0;
    });
  }

  bool shadowCorrection = true;  // of the frame being rendered (scene setting or option)

  // ---- environment lighting: rebuilt only when the scene's description changes ----
  std::unique_ptr<Environment> env;
  std::string envKey;
  cl::Buffer envDummyTexels, envDummyLevels, envDummySh;
  const cl::Buffer& envTexels() const { return env ? env->texels() : envDummyTexels; }
  const cl::Buffer& envLevels() const { return env ? env->levels() : envDummyLevels; }
  const cl::Buffer& envSh() const { return env ? env->sh() : envDummySh; }

  static std::string envDescKey(const EnvironmentDesc& e) {
    std::ostringstream k;
    k << e.file << '|' << e.intensity << '|' << e.rotateYDegrees << '|' << e.sky.sunElevationDeg << ','
      << e.sky.sunAzimuthDeg << ',' << e.sky.sunAngularDiameterDeg << ',' << e.sky.sunIrradiance << ','
      << e.sky.gradientExponent << ',' << e.sky.groundBlend << ',' << e.sky.width;
    for (const glm::vec3& c : {e.sky.sunColor, e.sky.zenith, e.sky.horizon, e.sky.ground}) k << ',' << c.x << ',' << c.y << ',' << c.z;
    return k.str();
  }

  // ---- background image: read and uploaded when the path changes ----
  std::string backgroundPath;
  int backgroundWidth = 0, backgroundHeight = 0;
  cl::Buffer background;

  void ensureBackground(const std::string& path) {
    if (path.empty()) {
      if (!background()) background = makeBuffer<cl_float4>(dev, "background placeholder", 1);
      backgroundPath.clear();
      backgroundWidth = backgroundHeight = 0;
      return;
    }
    if (path == backgroundPath) return;
    Image img = readImage(path);
    for (float v : img.rgba)
      if (!std::isfinite(v)) throw Error(path + ": background image holds a non-finite value");
    background = makeBuffer<cl_float4>(dev, "background image " + path, img.rgba.size() / 4,
                                       reinterpret_cast<const cl_float4*>(img.rgba.data()));
    backgroundPath = path;
    backgroundWidth = img.width;
    backgroundHeight = img.height;
  }

  void ensureEnvironment(const EnvironmentDesc& e) {
    if (!envDummyTexels()) {
      envDummyTexels = makeBuffer<cl_float4>(dev, "environment placeholder", 1);
      envDummyLevels = makeBuffer<gpu::ClhEnvLevel>(dev, "environment placeholder", 1);
      envDummySh = makeBuffer<cl_float>(dev, "environment placeholder", CLH_ENV_SH_FLOATS);
    }
    if (!e.enabled) {
      env.reset();
      envKey.clear();
      return;
    }
    const std::string key = envDescKey(e);
    if (env && key == envKey) return;
    Environment::Options o;
    o.intensity = e.intensity;
    o.rotateYDegrees = e.rotateYDegrees;
    env = std::make_unique<Environment>(e.file.empty() ? Environment::fromSky(dev, e.sky, o)
                                                       : Environment::fromFile(dev, e.file, o));
    envKey = key;
  }

  DispatchMode resolveMode(DispatchMode m) const {
    // CPU devices: the benchmark's dispatch section (bench/README.md) measured read-back
    // and over-launch level within noise on PoCL, persistent no better (two runs), and
    // read-back launches exactly the drawn strands, so it is the CPU default. GPUs:
    // not measured yet; over-launch avoids the host round trip between the pre-pass and
    // the strand pass (a pipeline bubble per groom on a discrete GPU), and surplus
    // work-groups leave after one load. Re-run `clhair_bench --only dispatch` on a GPU
    // and change this if it disagrees.
    if (m != DispatchMode::Auto) return m;
    return dev.info.isGpu ? DispatchMode::OverLaunch : DispatchMode::ReadBack;
  }

  void uploadScene(const Scene& s) {
    gpu::ClhSceneGpu sg;
    std::memset(&sg, 0, sizeof(sg));
    store4(sg.background, s.background, 1.0f);
    store4(sg.ambient, s.ambient, 1.0f);
    std::vector<gpu::ClhSphereGpu> sp(s.spheres.size());
    for (std::size_t i = 0; i < sp.size(); ++i) {
      store4(sp[i].center, s.spheres[i].center, s.spheres[i].radius);
      store4(sp[i].color, s.spheres[i].color, 1.0f);
    }
    std::vector<gpu::ClhPlaneGpu> pl(s.planes.size());
    for (std::size_t i = 0; i < pl.size(); ++i) {
      store4(pl[i].normal, s.planes[i].normal, s.planes[i].offset);
      store4(pl[i].color, s.planes[i].color, 1.0f);
    }
    if (s.lights.size() > CLH_MAX_LIGHTS)
      throw Error("scene has " + std::to_string(s.lights.size()) + " lights; at most " + std::to_string(CLH_MAX_LIGHTS) + " are supported");
    std::vector<gpu::ClhLightGpu> li(s.lights.size());
    for (std::size_t i = 0; i < li.size(); ++i) {
      const Light& l = s.lights[i];
      if (l.type == Light::Type::Point)
        store4(li[i].pos, l.position, 1.0f);
      else
        store4(li[i].pos, l.direction, 0.0f);
      store4(li[i].color, l.color * l.intensity, -1.0f);
    }
    int slot = 0;
    for (std::size_t i = 0; i < li.size(); ++i)
      if (s.lights[i].shadows && !s.grooms.empty() && slot < CLH_MAX_SHADOWS) li[i].color[3] = static_cast<float>(slot++);
    ensureEnvironment(s.environment);
    ensureBackground(s.backgroundImage);
    sg.bg_width = static_cast<gpu::clh_u32>(backgroundWidth);
    sg.bg_height = static_cast<gpu::clh_u32>(backgroundHeight);
    sg.env_levels = env ? (env->levelCount() | (s.environment.visible ? CLH_ENV_VISIBLE : 0u)) : 0u;
    sg.sphere_count = static_cast<gpu::clh_u32>(sp.size());
    sg.plane_count = static_cast<gpu::clh_u32>(pl.size());
    sg.light_count = static_cast<gpu::clh_u32>(li.size());
    upload(dev, scene, &sg, 1);
    spheres = makeBuffer(dev, "spheres", sp.size(), sp.data());
    planes = makeBuffer(dev, "planes", pl.size(), pl.data());
    lights = makeBuffer(dev, "lights", li.size(), li.data());
    uploadMeshes(s);
  }

  // World-space vertices, normals (area-weighted averages of the triangles' normals) and
  // triangles of every mesh instance, uploaded when the scene's meshes change; every
  // buffer is checked against the device's largest allocation (makeBuffer).
  void uploadMeshes(const Scene& s) {
    // the instances as uploaded (holding their meshes, so an address is never reused)
    const bool same = meshColors() && s.meshes.size() == uploadedMeshes.size() &&
                      std::equal(s.meshes.begin(), s.meshes.end(), uploadedMeshes.begin(),
                                 [](const MeshInstance& a, const MeshInstance& b) {
                                   return a.mesh == b.mesh && a.transform == b.transform && a.color == b.color;
                                 });
    if (same) return;
    std::uint64_t vertices = 0, triangles = 0;
    for (const MeshInstance& m : s.meshes) {
      if (!m.mesh) throw Error("mesh \"" + m.name + "\" has no geometry");
      validateTriangleMesh(*m.mesh, "mesh \"" + m.name + "\"");
      vertices += m.mesh->positions.size();
      triangles += m.mesh->indices.size() / 3;
    }
    if (vertices > 0xFFFFFFFFull || triangles > 0xFFFFFFFFull)
      throw Error("the scene's meshes hold " + std::to_string(vertices) + " vertices and " + std::to_string(triangles) +
                  " triangles; at most 2^32 - 1 of each are supported");
    std::vector<cl_float4> pos, nrm;
    std::vector<cl_uint4> tri;
    std::vector<cl_float4> col;
    pos.reserve(vertices);
    nrm.reserve(vertices);
    tri.reserve(triangles);
    for (std::size_t i = 0; i < s.meshes.size(); ++i) {
      const MeshInstance& m = s.meshes[i];
      const auto base = static_cast<cl_uint>(pos.size());
      std::vector<glm::vec3> world(m.mesh->positions.size()), normal(m.mesh->positions.size(), glm::vec3(0.0f));
      for (std::size_t v = 0; v < world.size(); ++v) world[v] = glm::vec3(m.transform * glm::vec4(m.mesh->positions[v], 1.0f));
      const std::vector<std::uint32_t>& idx = m.mesh->indices;
      for (std::size_t t = 0; t + 2 < idx.size(); t += 3) {
        const glm::vec3 n = glm::cross(world[idx[t + 1]] - world[idx[t]], world[idx[t + 2]] - world[idx[t]]);
        for (int k = 0; k < 3; ++k) normal[idx[t + k]] += n;
        tri.push_back({{base + idx[t], base + idx[t + 1], base + idx[t + 2], static_cast<cl_uint>(i)}});
      }
      for (std::size_t v = 0; v < world.size(); ++v) {
        const float len = glm::length(normal[v]);
        const glm::vec3 n = len > 0.0f && std::isfinite(len) ? normal[v] / len : glm::vec3(0.0f);
        pos.push_back({{world[v].x, world[v].y, world[v].z, 1.0f}});
        nrm.push_back({{n.x, n.y, n.z, 0.0f}});
      }
      col.push_back({{m.color.x, m.color.y, m.color.z, 1.0f}});
    }
    meshVertices = makeBuffer(dev, "mesh vertices (" + std::to_string(pos.size()) + ")", pos.size(), pos.data());
    meshNormals = makeBuffer(dev, "mesh normals (" + std::to_string(nrm.size()) + ")", nrm.size(), nrm.data());
    meshTriangles = makeBuffer(dev, "mesh triangles (" + std::to_string(tri.size()) + ")", tri.size(), tri.data());
    meshColors = makeBuffer(dev, "mesh colours", col.size(), col.data());
    meshVertexCount = static_cast<std::uint32_t>(pos.size());
    meshTriangleCount = static_cast<std::uint32_t>(tri.size());
    meshColorCount = static_cast<std::uint32_t>(col.size());
    uploadedMeshes = s.meshes;
  }

  // The scene's meshes over the analytic scene already in `color` / `depth` (a view of
  // width x height: the camera's or a light's); shade = false writes depth only.
  void drawMeshes(const cl::Buffer& v, cl::Buffer& colorOut, cl::Buffer& depthOut, int w, int h, bool shade) {
    if (meshTriangleCount == 0) return;
    // one word buffer for the camera's and the lights' views: sized for the larger
    std::size_t pixels = std::max(static_cast<std::size_t>(w) * static_cast<std::size_t>(h),
                                  static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    pixels = std::max(pixels, static_cast<std::size_t>(shadowRes) * static_cast<std::size_t>(shadowRes));
    if (bufferBytes(meshWords) < pixels * sizeof(cl_ulong))
      meshWords = makeBuffer<cl_ulong>(dev, "the mesh depth words (" + std::to_string(pixels) + " pixels)", pixels);
    meshStage.enqueue({&scene, &v,
                       {&meshVertices, &meshNormals, &meshTriangles, &meshColors, meshVertexCount, meshTriangleCount,
                        meshColorCount},
                       &lights, &shadowAll, &shadowOpaque, &shadowHair, &shadowOpacity, &envSh(), &meshWords, &colorOut,
                       &depthOut, w, h, shade},
                      &profiler);
  }

  // View-dependent groom parameters; returns false when the groom is entirely behind the camera.
  bool prepareGroomView(GroomResources& g, const glm::mat4& objToWorld, const glm::mat4& w2v,
                        const RenderOptions& options, float nearOverride = -1.0f, float farOverride = -1.0f) {
    gpu::ClhGroomGpu& p = g.params;
    glm::mat4 o2v = w2v * objToWorld;
    storeMat34(p.obj_to_view, o2v);
    storeMat34(p.obj_to_world, objToWorld);
    if (!depthRange(g.data.boundsMin, g.data.boundsMax, o2v, p.depth_near, p.depth_far)) return false;
    if (nearOverride > 0.0f) {  // a G-buffer shared by several grooms needs one depth mapping
      p.depth_near = nearOverride;
      p.depth_far = farOverride;
    }
    const HairMesh& mesh = *g.keepAlive;
    p.lod_enabled = options.lod < 0 ? (mesh.lod.enabled ? 1u : 0u) : static_cast<gpu::clh_u32>(options.lod);
    p.lod_lambda = mesh.lod.lambda * options.lodLambdaScale;
    p.total_strands = static_cast<gpu::clh_u32>(g.data.totalStrands);
    p.shadow_lod_correction = shadowCorrection ? 1u : 0u;
    upload(dev, g.groom, &p, 1);
    return true;
  }

  // ---- explicit grooms ----

  // Device tables of a StrandGroom (explicit_data.h); every buffer is checked against the
  // device's largest allocation before it is created.
  std::unique_ptr<ExplicitResources> buildExplicit(const StrandGroom& sg) {
    const std::string what = "groom \"" + sg.name + "\"";
    validateStrandGroom(sg, what);
    auto e = std::make_unique<ExplicitResources>();
    e->data = prepareExplicit(sg);
    ExplicitData& d = e->data;
    gpu::ClhGroomGpu& p = e->params;
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
    p.control_points = CLH_MAX_CONTROL_POINTS;  // C_full of the chunk LOD: step 1
    p.total_strands = static_cast<gpu::clh_u32>(d.totalStrands);
    const std::size_t K = d.chunks.size();
    // per-point file colour and thickness follow the points in the same buffer
    // (kernels/strands_explicit.cl reads them at point_count + k)
    p.look[2] = d.fileColor ? 1.0f : 0.0f;
    if (!d.fileLook.empty()) d.points.insert(d.points.end(), d.fileLook.begin(), d.fileLook.end());
    std::vector<glm::vec4>().swap(d.fileLook);
    e->points = makeBuffer<cl_float4>(dev, what + " strand points (" + std::to_string(d.totalPoints) + ")",
                                      d.points.size(), reinterpret_cast<const cl_float4*>(d.points.data()));
    e->strandOffsets = makeBuffer(dev, what + " strand offsets", d.strandOffsets.size(), d.strandOffsets.data());
    e->uv = d.uv.empty() ? makeBuffer<cl_uint>(dev, what + " root uv", 1)
                         : makeBuffer(dev, what + " root uv", d.uv.size(), d.uv.data());
    e->chunks = makeBuffer<cl_uint4>(dev, what + " chunk table", K, reinterpret_cast<const cl_uint4*>(d.chunks.data()));
    e->chunkBounds = makeBuffer<cl_float4>(dev, what + " chunk bounds", 2 * K,
                                           reinterpret_cast<const cl_float4*>(d.chunkBounds.data()));
    e->groom = makeBuffer<gpu::ClhGroomGpu>(dev, what + " parameters", 1, &p);
    e->lod = makeBuffer<cl_uint4>(dev, what + " LOD records", K);
    e->counts = makeBuffer<cl_uint>(dev, what + " strand counts", 2 * K);
    e->offsets = makeBuffer<cl_uint>(dev, what + " strand offsets per chunk", K + 2);
    std::vector<glm::vec4>().swap(d.points);  // on the device now
    return e;
  }

  ExplicitResources& explicitFor(const std::shared_ptr<const StrandGroom>& sg) {
    auto it = explicitGrooms.find(sg.get());
    if (it != explicitGrooms.end()) return *it->second;
    auto e = buildExplicit(*sg);
    e->keepAlive = sg;
    ExplicitResources& ref = *e;
    explicitGrooms[sg.get()] = std::move(e);
    return ref;
  }

  ExplicitStage::Inputs explicitInputs(ExplicitResources& e) {
    return {&e.groom, &e.points, &e.strandOffsets, &e.uv, &e.chunks, &e.chunkBounds, &e.lod, &e.counts, &e.offsets,
            static_cast<std::uint32_t>(e.data.chunks.size()), static_cast<std::uint32_t>(e.data.totalStrands),
            static_cast<std::uint32_t>(e.data.totalPoints), !e.data.uv.empty()};
  }

  // View-dependent parameters of an explicit groom, like prepareGroomView.
  bool prepareExplicitView(ExplicitResources& e, const glm::mat4& objToWorld, const glm::mat4& w2v,
                           const RenderOptions& options, float nearOverride = -1.0f, float farOverride = -1.0f) {
    gpu::ClhGroomGpu& p = e.params;
    const glm::mat4 o2v = w2v * objToWorld;
    storeMat34(p.obj_to_view, o2v);
    storeMat34(p.obj_to_world, objToWorld);
    if (!depthRange(e.data.boundsMin, e.data.boundsMax, o2v, p.depth_near, p.depth_far)) return false;
    if (nearOverride > 0.0f) {
      p.depth_near = nearOverride;
      p.depth_far = farOverride;
    }
    const StrandGroom& sg = *e.keepAlive;
    p.lod_enabled = options.lod < 0 ? (sg.lod.enabled ? 1u : 0u) : static_cast<gpu::clh_u32>(options.lod);
    p.lod_lambda = sg.lod.lambda * options.lodLambdaScale;
    p.hit_diameter_px = trueWidthOnly ? 0.0f : sg.appearance.minHitDiameterPx;
    p.shadow_lod_correction = shadowCorrection ? 1u : 0u;
    if (e.data.fileThickness) {
      // file thickness is in object units: scale it like the points (uniform part)
      const float scale = std::cbrt(std::fabs(glm::determinant(glm::mat3(objToWorld))));
      p.look[3] = scale;
      p.strand_width = std::max(e.data.meanThickness * scale, 1e-9f);  // LOD and shadow estimates
    }
    upload(dev, e.groom, &p, 1);
    return true;
  }

  // Object-space bounds of a groom instance's geometry (building its resources if needed).
  void groomBounds(const GroomInstance& gi, glm::vec3& lo, glm::vec3& hi) {
    if (gi.strands) {
      const ExplicitResources& e = explicitFor(gi.strands);
      lo = e.data.boundsMin;
      hi = e.data.boundsMax;
    } else {
      const GroomResources& g = groomFor(gi.mesh);
      lo = g.data.boundsMin;
      hi = g.data.boundsMax;
    }
  }

  std::uint32_t readWord(const cl::Buffer& buffer, std::size_t index) {
    std::uint32_t v = 0;
    clCall("reading a strand total", [&] {
      dev.queue.enqueueReadBuffer(buffer, CL_TRUE, index * sizeof(std::uint32_t), sizeof(std::uint32_t), &v);
      return 0;
    });
    return v;
  }

  // The styling reach in view units: the object-space margin times the largest axis scale.
  static float viewReach(const GroomResources& g, const glm::mat4& objToWorld) {
    float scale = std::max({glm::length(glm::vec3(objToWorld[0])), glm::length(glm::vec3(objToWorld[1])),
                            glm::length(glm::vec3(objToWorld[2]))});
    return g.data.styleMargin * scale;
  }

  StrandStage::Inputs strandInputs(GroomResources& g) {
    return {&g.groom, &g.bundles, &g.vertices, &g.lod, &g.offsets, &rootsQuad, &rootsTri};
  }

  // LOD in the view `viewBuffer` (the camera's, or a light's for the shadow passes).
  LodStage::Params lodParams(GroomResources& g, float reach, const cl::Buffer& viewBuffer) {
    return {&g.groom, &viewBuffer, &g.bundles, &g.vertices, reach, &g.lod, &g.counts, &g.offsets,
            static_cast<std::uint32_t>(g.data.bundles.size())};
  }
};

Renderer::Renderer(Device device) : impl_(std::make_unique<Impl>(std::move(device))) {}
Renderer::~Renderer() = default;

const Device& Renderer::device() const { return impl_->device; }

Frame Renderer::render(const Scene& s, const RenderOptions& options) {
  Impl& r = *impl_;
  r.ensureTarget(s.width, s.height, options.msaa);
  r.uploadScene(s);
  gpu::ClhViewGpu view = makeView(s.camera, s.width, s.height);
  view.samples = static_cast<gpu::clh_u32>(options.msaa);
  view.cx += options.jitterX;
  view.cy += options.jitterY;
  upload(r.dev, r.view, &view, 1);
  const glm::mat4 w2v = worldToView(s.camera);
  const DispatchMode mode = r.resolveMode(options.dispatch);
  const std::size_t pixels = static_cast<std::size_t>(s.width) * s.height;
  Frame frame;
  r.profiler.hostTiming = options.stageCores;
  if (options.rasterStats) {
    const cl_uint zero[4] = {0, 0, 0, 0};
    upload(r.dev, r.stats, zero, 4);
  }

  r.shadowCorrection = options.shadowLodCorrection < 0 ? s.shadows.lodCorrection : options.shadowLodCorrection == 1;
  {
    Impl::ShadowKey key = r.shadowKey(s, options);
    if (!options.reuseShadows || !r.shadowsValid || !(key == r.lastShadowKey)) {
      r.shadowsValid = false;  // until the passes are enqueued
      r.renderShadows(s, options);
      r.lastShadowKey = std::move(key);
      r.shadowsValid = true;
    }
  }
  r.opaque.enqueue({&r.scene, &r.view, &r.spheres, &r.planes, &r.lights, &r.shadowAll, &r.shadowOpaque, &r.shadowHair,
                    &r.shadowOpacity, &r.envTexels(), &r.envLevels(), &r.envSh(), &r.background, &r.color, &r.depth, s.width, s.height,
                    true},
                   &r.profiler);
  r.drawMeshes(r.view, r.color, r.depth, s.width, s.height, true);
  // per drawn groom: its chunk/bundle scan and the index of the drawn total in it
  std::vector<std::pair<const cl::Buffer*, std::size_t>> drawn;
  for (const GroomInstance& gi : s.grooms) {
    const cl::Buffer* groomParams = nullptr;
    const cl::Buffer* groomOffsets = nullptr;
    const gpu::ClhGroomGpu* groomRecord = nullptr;
    StrandStage::Raster rs{&r.view, &r.depth, &r.gbuffer, &r.stats, options.msaa, options.rasterStats, mode, 0};
    if (gi.strands) {
      ExplicitResources& e = r.explicitFor(gi.strands);
      if (!r.prepareExplicitView(e, gi.transform, w2v, options)) continue;
      const ExplicitStage::Inputs in = r.explicitInputs(e);
      drawn.push_back({&e.offsets, in.chunkCount});
      r.explicitStage.lod(in, r.view, &r.profiler);
      rs.strands = mode == DispatchMode::ReadBack ? r.explicitStage.readTotal(in) : in.strandCount;
      r.clearWords(r.gbuffer, pixels * r.layers);
      r.explicitStage.raster(in, rs, &r.profiler);
      groomParams = &e.groom;
      groomOffsets = &e.offsets;
      groomRecord = &e.params;
    } else {
      GroomResources& g = r.groomFor(gi.mesh);
      r.applyAo(g, options.ambientOcclusion != 0);
      if (!r.prepareGroomView(g, gi.transform, w2v, options)) continue;
      drawn.push_back({&g.offsets, g.data.bundles.size()});
      LodStage::Params lp = r.lodParams(g, Impl::viewReach(g, gi.transform), r.view);
      r.lod.enqueue(lp, &r.profiler);
      rs.strands = mode == DispatchMode::ReadBack ? r.lod.readTotal(lp) : static_cast<std::uint32_t>(g.data.totalStrands);
      r.clearWords(r.gbuffer, pixels * r.layers);
      r.strands.raster(r.strandInputs(g), rs, &r.profiler);
      groomParams = &g.groom;
      groomOffsets = &g.offsets;
      groomRecord = &g.params;
    }
    if (options.captureGBuffer) {  // the raster's inputs, before compositing changes the depth
      const auto* gb = reinterpret_cast<const std::uint8_t*>(groomRecord);
      const auto* vb = reinterpret_cast<const std::uint8_t*>(&view);
      frame.rasterGroom.assign(gb, gb + sizeof(gpu::ClhGroomGpu));
      frame.rasterView.assign(vb, vb + sizeof(gpu::ClhViewGpu));
      frame.rasterDepth.resize(pixels);
      clCall("reading the depth the hair was tested against", [&] {
        r.dev.queue.enqueueReadBuffer(r.depth, CL_TRUE, 0, pixels * sizeof(float), frame.rasterDepth.data());
        return 0;
      });
    }
    if (options.rasterOnly) continue;
    r.shade.enqueue({groomParams, &r.view, &r.scene, &r.lights, &r.shadowAll, &r.shadowOpaque, &r.shadowHair,
                     &r.shadowOpacity, &r.envTexels(), &r.envLevels(), &r.envSh(), &r.gbuffer, groomOffsets, &r.hair,
                     s.width, s.height, options.msaa},
                    &r.profiler);
    const FilterParams& fp = gi.hasFilter ? gi.filter : s.filter;
    const bool filtered = options.msaa == 1 && (options.filter < 0 ? fp.enabled : options.filter == 1);
    if (filtered) {
      r.uploadFilter(fp);
      r.filter.enqueue({groomParams, &r.view, &r.filterParams, &r.gbuffer, &r.hair, &r.filtered, s.width, s.height},
                       &r.profiler);
    }
    r.composite.enqueue({groomParams, &r.view, filtered ? &r.filtered : &r.hair, &r.gbuffer, &r.color, &r.depth, s.width,
                         s.height, options.msaa, filtered ? 2 : options.msaa},
                        &r.profiler);
  }

  frame.color.width = s.width;
  frame.color.height = s.height;
  frame.color.rgba.resize(pixels * 4);
  frame.depth.resize(pixels);
  clCall("reading the frame back", [&] {
    r.dev.queue.enqueueReadBuffer(r.color, CL_TRUE, 0, pixels * 4 * sizeof(float), frame.color.rgba.data());
    r.dev.queue.enqueueReadBuffer(r.depth, CL_TRUE, 0, pixels * sizeof(float), frame.depth.data());
    return 0;
  });
  for (const auto& [offsets, index] : drawn)
    if (index > 0) frame.stats.strandsDrawn += r.readWord(*offsets, index);
  frame.stats.shadowStrandsDrawn = r.shadowStrands;
  if (options.captureGBuffer) {
    frame.gbufferLayers = r.layers;
    frame.gbuffer.resize(pixels * r.layers);
    clCall("reading the G-buffer", [&] {
      if (drawn.empty())
        std::fill(frame.gbuffer.begin(), frame.gbuffer.end(), ~std::uint64_t(0));
      else
        r.dev.queue.enqueueReadBuffer(r.gbuffer, CL_TRUE, 0, frame.gbuffer.size() * sizeof(cl_ulong), frame.gbuffer.data());
      return 0;
    });
  }
  if (options.rasterStats) {
    cl_uint st[4];
    clCall("reading raster statistics", [&] {
      r.dev.queue.enqueueReadBuffer(r.stats, CL_TRUE, 0, sizeof(st), st);
      return 0;
    });
    frame.stats.pixelWrites = st[0];
    frame.stats.atomicsIssued = st[1];
    frame.stats.atomicsSkipped = st[2];
    frame.stats.segmentsDrawn = st[3];
  }
  frame.timings = r.profiler.collect();
  return frame;
}

Frame Renderer::renderReference(const Scene& scene, int spp) {
  if (spp < 1 || spp > 65536) throw Error("reference: --spp " + std::to_string(spp) + " is outside 1..65536");
  // true width only: no minimum hit diameter
  Scene s = scene;
  for (GroomInstance& g : s.grooms) {
    if (g.mesh && g.mesh->appearance.minHitDiameterPx != 0.0f) {
      HairMesh m = *g.mesh;
      m.appearance.minHitDiameterPx = 0.0f;
      g.mesh = std::make_shared<const HairMesh>(std::move(m));
    }
  }
  // explicit grooms keep their (large) device tables: the passes ignore their minimum
  struct TrueWidth {
    bool& flag;
    explicit TrueWidth(bool& f) : flag(f) { flag = true; }
    ~TrueWidth() { flag = false; }
  } trueWidth(impl_->trueWidthOnly);
  RenderOptions o;
  o.lod = 0;
  o.msaa = 1;
  o.filter = 0;
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
      for (std::size_t t = 0; t < sum.timings.size() && t < f.timings.size(); ++t) sum.timings[t].ms += f.timings[t].ms;
    }
  }
  for (std::size_t k = 0; k < acc.size(); ++k) sum.color.rgba[k] = static_cast<float>(acc[k] / spp);
  return sum;
}

StrandSet Renderer::generateStrands(const HairMesh& mesh, float lod) {
  Impl& r = *impl_;
  validateHairMesh(mesh, mesh.name);
  if (!(lod > 0.0f && lod <= 1.0f)) throw Error("strand export: LOD value " + std::to_string(lod) + " is outside (0, 1]");
  auto g = r.buildGroom(mesh, false);
  Impl::Exported e = r.exportStrands(*g, mesh, lod);
  StrandSet out;
  const std::uint32_t total = e.total;
  if (total == 0) return out;
  const std::size_t slots = static_cast<std::size_t>(total) * CLH_MAX_CONTROL_POINTS;
  std::vector<cl_float4> p(slots), t(slots);
  out.pointCounts.resize(total);
  clCall("reading exported strands", [&] {
    r.dev.queue.enqueueReadBuffer(e.points, CL_TRUE, 0, slots * sizeof(cl_float4), p.data());
    r.dev.queue.enqueueReadBuffer(e.tangents, CL_TRUE, 0, slots * sizeof(cl_float4), t.data());
    r.dev.queue.enqueueReadBuffer(e.counts, CL_TRUE, 0, total * sizeof(cl_uint), out.pointCounts.data());
    return 0;
  });
  std::vector<cl_uint> offsets(g->data.bundles.size() + 1);
  clCall("reading strand offsets", [&] {
    r.dev.queue.enqueueReadBuffer(g->offsets, CL_TRUE, 0, offsets.size() * sizeof(cl_uint), offsets.data());
    return 0;
  });
  out.bundleOf.resize(total);
  for (std::size_t b = 0; b + 1 < offsets.size(); ++b)
    for (cl_uint i = offsets[b]; i < offsets[b + 1] && i < total; ++i) out.bundleOf[i] = static_cast<std::uint32_t>(b);
  for (std::uint32_t s2 = 0; s2 < total; ++s2) {
    std::size_t base = static_cast<std::size_t>(s2) * CLH_MAX_CONTROL_POINTS;
    for (std::uint32_t k = 0; k < out.pointCounts[s2] && k < CLH_MAX_CONTROL_POINTS; ++k) {
      const cl_float4& q = p[base + k];
      const cl_float4& tq = t[base + k];
      out.points.insert(out.points.end(), {q.s[0], q.s[1], q.s[2]});
      out.tangents.insert(out.tangents.end(), {tq.s[0], tq.s[1], tq.s[2]});
      out.w.push_back(q.s[3]);
    }
  }
  return out;
}

StrandSet Renderer::generateStrands(const StrandGroom& groom, float lod) {
  Impl& r = *impl_;
  if (!(lod > 0.0f && lod <= 1.0f)) throw Error("strand export: LOD value " + std::to_string(lod) + " is outside (0, 1]");
  auto e = r.buildExplicit(groom);
  e->params.lod_enabled = 0;
  upload(r.dev, e->groom, &e->params, 1);
  // the records lod_chunks would write with every chunk at LOD value `lod`
  const std::size_t K = e->data.chunks.size();
  const gpu::clh_u32 cfull = CLH_MAX_CONTROL_POINTS;
  const gpu::clh_u32 C = gpu::clh_lod_control_points(lod, 3u, cfull);
  const float gamma = gpu::clh_lod_morph(lod, 3u, cfull, groom.lod.morphWindow);
  std::uint32_t lodBits, gammaBits;
  std::memcpy(&lodBits, &lod, 4);
  std::memcpy(&gammaBits, &gamma, 4);
  std::vector<cl_uint4> records(K);
  std::vector<cl_uint> offsets(K + 2, 0);
  for (std::size_t c = 0; c < K; ++c) {
    const glm::uvec4& chunk = e->data.chunks[c];
    float delta;
    std::memcpy(&delta, &chunk.z, 4);
    const gpu::clh_u32 n = gpu::clh_lod_strands(lod, chunk.y, delta);
    records[c] = {{n, C, lodBits, gammaBits}};
    offsets[c + 1] = offsets[c] + n;
  }
  offsets[K + 1] = static_cast<cl_uint>(e->data.totalStrands);
  upload(r.dev, e->lod, records.data(), K);
  upload(r.dev, e->offsets, offsets.data(), K + 2);
  const std::uint32_t total = offsets[K];
  const ExplicitStage::Inputs in = r.explicitInputs(*e);
  const std::size_t P = e->data.totalPoints, S = e->data.totalStrands;
  cl::Buffer points = makeBuffer<cl_float4>(r.dev, "exported strand points", P);
  cl::Buffer tangents = makeBuffer<cl_float4>(r.dev, "exported strand tangents", P);
  std::vector<cl_uint> counts(S, 0);
  cl::Buffer countBuf = makeBuffer<cl_uint>(r.dev, "exported strand point counts", S, counts.data());
  r.explicitStage.exportStrands(in, total, points, tangents, countBuf, nullptr);
  std::vector<cl_float4> p(P), t(P);
  clCall("reading exported strands", [&] {
    r.dev.queue.enqueueReadBuffer(points, CL_TRUE, 0, P * sizeof(cl_float4), p.data());
    r.dev.queue.enqueueReadBuffer(tangents, CL_TRUE, 0, P * sizeof(cl_float4), t.data());
    r.dev.queue.enqueueReadBuffer(countBuf, CL_TRUE, 0, S * sizeof(cl_uint), counts.data());
    return 0;
  });
  StrandSet out;
  for (std::size_t st = 0; st < S; ++st) {
    const std::uint32_t M = counts[st];
    if (M == 0) continue;
    const std::uint32_t first = e->data.strandOffsets[st];
    out.pointCounts.push_back(M);
    out.bundleOf.push_back(static_cast<std::uint32_t>(st / kChunkStrands));
    out.sourceStrand.push_back(e->data.sourceStrand[st]);
    for (std::uint32_t j = 0; j < M; ++j) {
      const cl_float4& q = p[first + j];
      const cl_float4& tq = t[first + j];
      out.points.insert(out.points.end(), {q.s[0], q.s[1], q.s[2]});
      out.tangents.insert(out.tangents.end(), {tq.s[0], tq.s[1], tq.s[2]});
      out.w.push_back(q.s[3]);
    }
  }
  return out;
}

std::uint64_t Renderer::groomDeviceBytes(const GroomInstance& groom) {
  Impl& r = *impl_;
  if (groom.strands) {
    const ExplicitResources& e = r.explicitFor(groom.strands);
    std::uint64_t sum = 0;
    for (const cl::Buffer* b : {&e.points, &e.strandOffsets, &e.uv, &e.chunks, &e.chunkBounds, &e.groom, &e.lod,
                                &e.counts, &e.offsets})
      sum += bufferBytes(*b);
    return sum;
  }
  if (!groom.mesh) throw Error("groom \"" + groom.name + "\" has neither a hair mesh nor strands");
  const GroomResources& g = r.groomFor(groom.mesh);
  std::uint64_t sum = 0;
  for (const cl::Buffer* b : {&g.vertices, &g.bundles, &g.groom, &g.lod, &g.counts, &g.offsets}) sum += bufferBytes(*b);
  return sum;
}

std::vector<float> Renderer::bakeAmbientOcclusion(const HairMesh& mesh) {
  validateHairMesh(mesh, mesh.name);
  return impl_->bakeAo(mesh);
}

}  // namespace clhair
