// scene_gpu.cpp — see scene_gpu.h.
#include "frame/scene_gpu.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include <glm/geometric.hpp>

#include "cl/buffers.h"
#include "clhair/image.h"
#include "stages/view_math.h"

namespace clhair {

namespace {

std::string envDescKey(const EnvironmentDesc& e) {
  std::ostringstream k;
  k << e.file << '|' << e.intensity << '|' << e.rotateYDegrees << '|' << e.sky.sunElevationDeg
    << ',' << e.sky.sunAzimuthDeg << ',' << e.sky.sunAngularDiameterDeg << ','
    << e.sky.sunIrradiance << ',' << e.sky.gradientExponent << ',' << e.sky.groundBlend << ','
    << e.sky.width;
  for (const glm::vec3& c : {e.sky.sunColor, e.sky.zenith, e.sky.horizon, e.sky.ground})
    k << ',' << c.x << ',' << c.y << ',' << c.z;
  return k.str();
}

// Writes `v` into a grow-only buffer unless it holds it already (`last`: what it holds).
template <typename T>
void uploadTable(Device::Impl& dev, cl::Buffer& buffer, std::size_t& capacity,
                 std::vector<unsigned char>& last, const std::string& what,
                 const std::vector<T>& v) {
  const cl_mem before = buffer();
  ensureCapacity<T>(dev, buffer, capacity, what, v.size());
  if (buffer() != before) last.clear();
  uploadChanged(dev, buffer, last, v.data(), v.size());
}

}  // namespace

SceneGpu::SceneGpu(Device::Impl& dev) : dev_(dev), opaque_(dev), meshStage_(dev) {
  scene_ = makeBuffer<gpu::ClhSceneGpu>(dev, "scene parameters", 1);
  envDummyTexels_ = makeBuffer<cl_float4>(dev, "environment placeholder", 1);
  envDummyLevels_ = makeBuffer<gpu::ClhEnvLevel>(dev, "environment placeholder", 1);
  envDummySh_ = makeBuffer<cl_float>(dev, "environment placeholder", CLH_ENV_SH_FLOATS);
  background_ = makeBuffer<cl_float4>(dev, "background placeholder", 1);
}

SceneGpu::~SceneGpu() = default;

void SceneGpu::upload(const Scene& s) {
  if (s.lights.size() > CLH_MAX_LIGHTS)
    throw Error("scene has " + std::to_string(s.lights.size()) + " lights; at most " +
                std::to_string(CLH_MAX_LIGHTS) + " are supported");
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
  std::vector<gpu::ClhLightGpu> li(s.lights.size());
  for (std::size_t i = 0; i < li.size(); ++i) {
    const Light& l = s.lights[i];
    if (l.type == Light::Type::Point)
      store4(li[i].pos, l.position, 1.0f);
    else
      store4(li[i].pos, l.direction, 0.0f);
    store4(li[i].color, l.color * l.intensity, -1.0f);  // w: shadow slot, -1 none
  }
  // shadow slots in light order, as ShadowMaps assigns them
  int slot = 0;
  for (std::size_t i = 0; i < li.size(); ++i)
    if (s.lights[i].shadows && !s.grooms.empty() && slot < CLH_MAX_SHADOWS)
      li[i].color[3] = static_cast<float>(slot++);
  ensureEnvironment(s.environment);
  ensureBackground(s.backgroundImage);
  sg.bg_width = static_cast<gpu::clh_u32>(backgroundWidth_);
  sg.bg_height = static_cast<gpu::clh_u32>(backgroundHeight_);
  sg.env_levels = env_ ? (env_->levelCount() | (s.environment.visible ? CLH_ENV_VISIBLE : 0u)) : 0u;
  sg.sphere_count = static_cast<gpu::clh_u32>(sp.size());
  sg.plane_count = static_cast<gpu::clh_u32>(pl.size());
  sg.light_count = static_cast<gpu::clh_u32>(li.size());
  uploadChanged(dev_, scene_, sent_[0], &sg, 1);
  uploadTable(dev_, spheres_, sphereCapacity_, sent_[1], "spheres", sp);
  uploadTable(dev_, planes_, planeCapacity_, sent_[2], "planes", pl);
  uploadTable(dev_, lights_, lightCapacity_, sent_[3], "lights", li);
  sphereCount_ = sg.sphere_count;
  planeCount_ = sg.plane_count;
  lightCount_ = sg.light_count;
  uploadMeshes(s);
  if (meshTriangleCount_ > 0) {
    // The mesh pass's word buffer, sized now for the camera and the shadow maps: allocated
    // before the grooms' temporaries come and go, as ShadowMaps::reserve explains.
    const std::size_t res = static_cast<std::size_t>(std::max(s.shadows.resolution, 0));
    const std::size_t pixels =
        std::max(static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height), res * res);
    ensureCapacity<cl_ulong>(dev_, meshWords_, meshWordCapacity_,
                             "the mesh depth words (" + std::to_string(pixels) + " pixels)",
                             pixels);
  }
}

std::vector<const cl::Buffer*> SceneGpu::buffers() const {
  std::vector<const cl::Buffer*> b = {
      &scene_,          &spheres_,       &planes_,     &lights_,    &meshVertices_,
      &meshNormals_,    &meshTriangles_, &meshColors_, &meshWords_, &envDummyTexels_,
      &envDummyLevels_, &envDummySh_,    &background_};
  if (env_) b.insert(b.end(), {&env_->texels(), &env_->levels(), &env_->sh()});
  return b;
}

bool SceneGpu::environmentChanges(const Scene& s) const {
  return s.environment.enabled && (!env_ || envDescKey(s.environment) != envKey_);
}

LightingInputs SceneGpu::lighting(const ShadowMapInputs& maps) const {
  LightingInputs l;
  l.scene = &scene_;
  l.lights = &lights_;
  l.lightCount = lightCount_;
  l.shadows = maps;
  l.env.texels = env_ ? &env_->texels() : &envDummyTexels_;
  l.env.levels = env_ ? &env_->levels() : &envDummyLevels_;
  l.env.sh = env_ ? &env_->sh() : &envDummySh_;
  return l;
}

void SceneGpu::drawOpaque(const ViewTarget& target, const ShadowMapInputs& maps, cl::Buffer& color,
                          cl::Buffer& depth, bool shade, Profiler* profiler) {
  OpaqueStage::Params op;
  op.target = target;
  op.lighting = lighting(maps);
  op.spheres = &spheres_;
  op.planes = &planes_;
  op.sphereCount = sphereCount_;
  op.planeCount = planeCount_;
  op.background = &background_;
  op.backgroundTexels =
      std::max<std::size_t>(1, std::size_t(backgroundWidth_) * std::size_t(backgroundHeight_));
  op.color = &color;
  op.depth = &depth;
  op.shade = shade;
  opaque_.enqueue(op, profiler);
  if (meshTriangleCount_ == 0) return;
  // one word buffer for the camera's and the lights' views, grown to the largest
  ensureCapacity<cl_ulong>(dev_, meshWords_, meshWordCapacity_,
                           "the mesh depth words (" + std::to_string(target.pixels()) + " pixels)",
                           target.pixels());
  MeshStage::Params mp;
  mp.target = target;
  mp.lighting = op.lighting;
  mp.geometry = {&meshVertices_,   &meshNormals_,      &meshTriangles_, &meshColors_,
                 meshVertexCount_, meshTriangleCount_, meshColorCount_};
  mp.words = &meshWords_;
  mp.color = &color;
  mp.depth = &depth;
  mp.shade = shade;
  meshStage_.enqueue(mp, profiler);
}

// World-space vertices, normals (area-weighted averages of the triangles' normals) and
// triangles of every mesh instance, uploaded when the scene's meshes change; every buffer
// is checked against the device's largest allocation (makeBuffer).
void SceneGpu::uploadMeshes(const Scene& s) {
  const bool same =
      meshesUploaded_ && s.meshes.size() == uploadedMeshes_.size() &&
      std::equal(s.meshes.begin(), s.meshes.end(), uploadedMeshes_.begin(),
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
    throw Error("the scene's meshes hold " + std::to_string(vertices) + " vertices and " +
                std::to_string(triangles) + " triangles; at most 2^32 - 1 of each are supported");
  std::vector<cl_float4> pos, nrm, col;
  std::vector<cl_uint4> tri;
  pos.reserve(vertices);
  nrm.reserve(vertices);
  tri.reserve(triangles);
  for (std::size_t i = 0; i < s.meshes.size(); ++i) {
    const MeshInstance& m = s.meshes[i];
    const auto base = static_cast<cl_uint>(pos.size());
    std::vector<glm::vec3> world(m.mesh->positions.size()),
        normal(m.mesh->positions.size(), glm::vec3(0.0f));
    for (std::size_t v = 0; v < world.size(); ++v)
      world[v] = glm::vec3(m.transform * glm::vec4(m.mesh->positions[v], 1.0f));
    const std::vector<std::uint32_t>& idx = m.mesh->indices;
    for (std::size_t t = 0; t + 2 < idx.size(); t += 3) {
      const glm::vec3 n =
          glm::cross(world[idx[t + 1]] - world[idx[t]], world[idx[t + 2]] - world[idx[t]]);
      for (int k = 0; k < 3; ++k) normal[idx[t + k]] += n;
      tri.push_back(
          {{base + idx[t], base + idx[t + 1], base + idx[t + 2], static_cast<cl_uint>(i)}});
    }
    for (std::size_t v = 0; v < world.size(); ++v) {
      const float len = glm::length(normal[v]);
      const glm::vec3 n = len > 0.0f && std::isfinite(len) ? normal[v] / len : glm::vec3(0.0f);
      pos.push_back({{world[v].x, world[v].y, world[v].z, 1.0f}});
      nrm.push_back({{n.x, n.y, n.z, 0.0f}});
    }
    col.push_back({{m.color.x, m.color.y, m.color.z, 1.0f}});
  }
  meshVertices_ = makeBuffer(dev_, "mesh vertices (" + std::to_string(pos.size()) + ")", pos.size(),
                             pos.data());
  meshNormals_ =
      makeBuffer(dev_, "mesh normals (" + std::to_string(nrm.size()) + ")", nrm.size(), nrm.data());
  meshTriangles_ = makeBuffer(dev_, "mesh triangles (" + std::to_string(tri.size()) + ")",
                              tri.size(), tri.data());
  meshColors_ = makeBuffer(dev_, "mesh colours", col.size(), col.data());
  meshVertexCount_ = static_cast<std::uint32_t>(pos.size());
  meshTriangleCount_ = static_cast<std::uint32_t>(tri.size());
  meshColorCount_ = static_cast<std::uint32_t>(col.size());
  uploadedMeshes_ = s.meshes;
  meshesUploaded_ = true;
}

void SceneGpu::ensureEnvironment(const EnvironmentDesc& e) {
  if (!e.enabled) {
    env_.reset();
    envKey_.clear();
    return;
  }
  const std::string key = envDescKey(e);
  if (env_ && key == envKey_) return;
  Environment::Options o;
  o.intensity = e.intensity;
  o.rotateYDegrees = e.rotateYDegrees;
  env_ = std::make_unique<Environment>(e.file.empty() ? Environment::fromSky(dev_, e.sky, o)
                                                      : Environment::fromFile(dev_, e.file, o));
  envKey_ = key;
}

void SceneGpu::ensureBackground(const std::string& path) {
  if (path.empty()) {
    if (!backgroundPath_.empty())
      background_ = makeBuffer<cl_float4>(dev_, "background placeholder", 1);
    backgroundPath_.clear();
    backgroundWidth_ = backgroundHeight_ = 0;
    return;
  }
  if (path == backgroundPath_) return;
  Image img = readImage(path);
  for (float v : img.rgba)
    if (!std::isfinite(v)) throw Error(path + ": background image holds a non-finite value");
  background_ = makeBuffer<cl_float4>(dev_, "background image " + path, img.rgba.size() / 4,
                                      reinterpret_cast<const cl_float4*>(img.rgba.data()));
  backgroundPath_ = path;
  backgroundWidth_ = img.width;
  backgroundHeight_ = img.height;
}

}  // namespace clhair
