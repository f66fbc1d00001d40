// scene_gpu.h — the scene on the device, everything but the grooms: its parameter record
// (background, ambient, counts), spheres, planes and lights, the triangle meshes in world
// space, the prefiltered environment and the background image. upload() refreshes what a
// frame changed: small tables are rewritten in place (their buffers grow, never shrink),
// meshes are rebuilt only when the scene's meshes or their transforms change, the
// environment only when its description changes, the background only when its path does.
// drawOpaque() renders all of it into a view's colour and depth (or depth only, for a
// light).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "clhair/scene.h"
#include "lighting/environment.h"
#include "stages/mesh_stage.h"
#include "stages/opaque_stage.h"

namespace clhair {

class SceneGpu {
 public:
  explicit SceneGpu(Device::Impl& dev);
  ~SceneGpu();
  void upload(const Scene& s);
  // Whether upload(s) builds a new environment (prefiltering it waits for the device).
  bool environmentChanges(const Scene& s) const;
  // Every buffer the opaque and shading kernels may read from the scene (frame graph).
  std::vector<const cl::Buffer*> buffers() const;
  // The lighting the shading passes read, with the given shadow maps.
  LightingInputs lighting(const ShadowMapInputs& maps) const;
  // Analytic primitives, then meshes, into `color` / `depth` of `target`.
  void drawOpaque(const ViewTarget& target, const ShadowMapInputs& maps, cl::Buffer& color,
                  cl::Buffer& depth, bool shade, Profiler* profiler);

 private:
  void uploadMeshes(const Scene& s);
  void ensureEnvironment(const EnvironmentDesc& e);
  void ensureBackground(const std::string& path);

  Device::Impl& dev_;
  OpaqueStage opaque_;
  MeshStage meshStage_;
  cl::Buffer scene_;
  cl::Buffer spheres_, planes_, lights_;
  std::size_t sphereCapacity_ = 0, planeCapacity_ = 0, lightCapacity_ = 0;
  std::uint32_t sphereCount_ = 0, planeCount_ = 0, lightCount_ = 0;
  std::vector<unsigned char> sent_[4];  // what scene_, spheres_, planes_, lights_ hold
  // the scene's triangle meshes in world space and the instances they were built from
  // (holding their meshes, so an address is never reused)
  cl::Buffer meshVertices_, meshNormals_, meshTriangles_, meshColors_, meshWords_;
  std::size_t meshWordCapacity_ = 0;
  std::uint32_t meshVertexCount_ = 0, meshTriangleCount_ = 0, meshColorCount_ = 0;
  std::vector<MeshInstance> uploadedMeshes_;
  bool meshesUploaded_ = false;
  // environment lighting and its description; placeholders when there is none
  std::unique_ptr<Environment> env_;
  std::string envKey_;
  cl::Buffer envDummyTexels_, envDummyLevels_, envDummySh_;
  // background image
  std::string backgroundPath_;
  int backgroundWidth_ = 0, backgroundHeight_ = 0;
  cl::Buffer background_;
};

}  // namespace clhair
