// presets.h — the groom generator behind `clhair groom --preset NAME -o FILE`.
//
// long_wavy     long wavy hair on a head-sized scalp, ~127k strands (the seeds' scale)
// curly_medium  medium-length ringlet curls, ~100k strands
// fur_sphere    short fur on a sphere, ~160k strands
// tiny          three bundles on a small patch, for fast tests
#pragma once

#include <string>
#include <vector>

#include "clhair/hair_mesh.h"

namespace clhair {

std::vector<std::string> groomPresetNames();
// Throws clhair::Error for an unknown name.
HairMesh makeGroomPreset(const std::string& name);

}  // namespace clhair
