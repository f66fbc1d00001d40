// groom_stages.h — the groom stages of a test device (the shared one unless given), as a Renderer
// holds them, for tests that build a groom's device form (HairMeshGpu) without a renderer.
#pragma once

#include "groom/groom_gpu.h"
#include "groom/hair_mesh_gpu.h"
#include "stages/ao_stage.h"
#include "test_util.h"

namespace clhair::test {

struct GroomStagesOnDevice {
  explicit GroomStagesOnDevice(Device::Impl& d = *sharedDevice().impl()) : dev(d) {}
  Device::Impl& dev;
  LodStage lod{dev};
  StrandStage strands{dev};
  ExplicitStage explicitStrands{dev};
  AoStage ao{dev};
  RootSetsGpu roots;
  GroomStages stages{dev, lod, strands, explicitStrands, ao, roots};
};

}  // namespace clhair::test
