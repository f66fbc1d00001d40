// ao_field.h — the AO field of a strand file: the ambient occlusion a hair mesh bakes per
// layer vertex, for a groom that has none. Its fibres are splatted on the host into a grid
// of fibre extinction (as kernels/ao.cl's ao_voxelize does for generated strands: length
// times diameter per volume), one voxel of margin on every side; then the device averages
// the visibility of 64 directions from every voxel centre (AoStage::field), and the shading
// reads it trilinearly at the shaded point (kernels/common/ao_field.h). The bake depends
// only on the device and the grid, so it is kept with the compiled programs.
//
// The scene's opaque spheres and triangle meshes inside the grid block rays too (a head under
// the hair, which a hair mesh's bake has as its scalp): they are added as opaque voxels
// for each placement of the groom, so a field belongs to a groom, its transform and the
// geometry around it. Left out, against the path reference: opaque planes, geometry
// outside the grid, and the light opaque surfaces reflect.
#pragma once

#include <cstdint>
#include <vector>

#include "clhair/scene.h"
#include "groom/explicit_data.h"
#include "stages/ao_stage.h"

namespace clhair {

struct AoDensity {
  AoStage::Grid grid;
  std::vector<std::uint32_t> density;  // fixed point, AO_FIXED per unit of extinction
};

// Voxels along the groom's longest side (the margin excluded): about 8 segments per voxel
// of the groom's bounding cube (a sparser grid's densities are mostly noise), from 8 to 48.
constexpr int kAoFieldMinCells = 8, kAoFieldMaxCells = 48;

// The density grid of `d`'s stored strands (points in object space, before they go to the
// device; d.fileLook still apart), each standing for `represented` fibres (children), of
// diameter `width` (object units) unless the file gives thicknesses, times the file's
// per-point opacity when it has one. Empty when the groom has no extent.
AoDensity splatAoDensity(const ExplicitData& d, float width, float represented);

// `d` with the scene's opaque spheres and meshes (world space) marked as opaque voxels, for
// the groom placed by `objToWorld`.
AoDensity withOccluders(const AoDensity& d, const Scene& scene, const glm::mat4& objToWorld);

// The field of `density` on the device, from the cache when the same grid was baked before.
AoField bakeAoField(Device::Impl& dev, AoStage& stage, const AoDensity& density);

}  // namespace clhair
