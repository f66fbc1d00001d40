// lod_far.h — the benchmark's lodfar section: does LOD pay at a distance? The default scene
// (assets/scenes/default.json: the long_wavy groom, a shadowed directional light) framed far
// at the quality size, maps rebuilt every frame: the strand and shadow stages with LOD off,
// with LOD (the lights' passes capped by the camera's LOD, the default), with the light's
// view alone, and with full-detail maps; the strand pass's dispatch sizing with LOD; and
// over the pixels the hair's shadow darkens, the FLIP between the shadowed images.
#pragma once

#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "clhair/renderer.h"

namespace clhair::bench {

struct LodFarOptions {
  std::string scene;  // assets/scenes/default.json
  int width = 960, height = 540;
  int runs = 3, warmup = 1;
};

void lodFarSection(Renderer& renderer, const LodFarOptions& o, std::ostringstream& md,
                   nlohmann::json& report);

}  // namespace clhair::bench
