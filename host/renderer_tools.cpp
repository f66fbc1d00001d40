// renderer_tools.cpp — the Renderer calls that are not one frame: the jittered reference
// (many frames averaged), strand export of a hair mesh or strand file, the AO bake, and
// the device footprint and release of cached grooms.
#include <cmath>

#include "groom/strand_file_gpu.h"
#include "renderer_impl.h"

namespace clhair {

Frame Renderer::renderReference(const Scene& s, int spp) {
  if (spp < 1 || spp > 65536)
    throw Error("reference: --spp " + std::to_string(spp) + " is outside 1..65536");
  RenderOptions o;
  o.lod = 0;
  o.msaa = 1;
  o.filter = 0;
  o.trueWidth = true;  // no minimum hit diameter
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
      for (std::size_t k = 0; k < sum.depth.size(); ++k)
        sum.depth[k] = std::min(sum.depth[k], f.depth[k]);
      for (std::size_t k = 0; k < sum.timings.size() && k < f.timings.size(); ++k)
        sum.timings[k].ms += f.timings[k].ms;
    }
  }
  for (std::size_t k = 0; k < acc.size(); ++k) sum.color.rgba[k] = static_cast<float>(acc[k] / spp);
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
