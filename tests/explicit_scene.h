// explicit_scene.h — the small scene the explicit strand tests render a groom in (one
// shadowed directional light, the groom alone), shared by test_explicit.cpp and
// test_explicit_round_trip.cpp.
#pragma once

#include <utility>

#include <glm/geometric.hpp>

#include "clhair/scene.h"

namespace clhair::explicit_test {

// A small scene around `groom`: one shadowed directional light.
inline Scene sceneAround(GroomInstance groom, int w, int h) {
  Scene s;
  s.width = w;
  s.height = h;
  s.background = glm::vec3(0.1f, 0.2f, 0.3f);
  Light l;
  l.direction = glm::normalize(glm::vec3(0.3f, 1.0f, 0.6f));
  l.intensity = 2.0f;
  l.shadows = true;
  s.lights.push_back(l);
  s.shadows.resolution = 128;
  s.grooms.push_back(std::move(groom));
  return s;
}

}  // namespace clhair::explicit_test
