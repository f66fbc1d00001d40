// animation_scenes.h — the small animated scenes that the animation tests
// (test_animation.cpp) and the frame-range tests (test_frame_range.cpp) share: a 64x48 scene
// of the tiny groom, the tiny groom's rest cage animated, per-frame strand files, and the
// check of a refused CLI render.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "clhair/animation.h"
#include "clhair/hair_mesh.h"
#include "io/cyhair.h"
#include "test_util.h"

namespace clhair::test {

inline void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

// A 64x48 scene of the tiny groom (4 layers of 7 vertices); `groom` adds to its groom entry,
// `camera` to its camera.
inline nlohmann::json tinyScene(const nlohmann::json& groom = nlohmann::json::object(),
                                const nlohmann::json& camera = nlohmann::json::object()) {
  nlohmann::json g = {{"file", assetPath("grooms/tiny.hairmesh.json")}};
  g.update(groom);
  nlohmann::json c = {{"position", {0.0, 0.03, 0.2}}, {"target", {0.0, 0.025, 0.0}}, {"fov", 35}};
  c.update(camera);
  return nlohmann::json{{"resolution", {64, 48}},
                        {"camera", c},
                        {"lights", {{{"type", "directional"}, {"direction", {0.3, 0.8, 0.5}}}}},
                        {"grooms", {g}}};
}

inline std::string writeScene(const std::string& dir, const nlohmann::json& scene,
                              const std::string& name = "scene.json") {
  const std::string path = dir + "/" + name;
  writeText(path, scene.dump(2));
  return path;
}

// The tiny groom's rest cage repeated `frames` times, each frame's tips moved by `tipShift`
// times the frame index along +x.
inline CageAnimation restCage(int frames, float tipShift = 0.0f) {
  const HairMesh m = loadHairMesh(assetPath("grooms/tiny.hairmesh.json"));
  CageAnimation c;
  c.frames = static_cast<std::uint32_t>(frames);
  c.vertices = static_cast<std::uint32_t>(m.positions.size());
  for (int f = 0; f < frames; ++f)
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
      glm::vec3 p = m.positions[i];
      if (i >= static_cast<std::size_t>(m.layerCount - 1) * m.vertexCount)
        p.x += tipShift * static_cast<float>(f);
      c.positions.push_back(p);
    }
  return c;
}

// A cyHair file of three 4-point strands hanging from y = 0.03 near the tiny groom's
// position, every point shifted by `dx` along x.
inline void writeStrandFrame(const std::string& path, float dx) {
  CyHair h;
  for (int s = 0; s < 3; ++s) {
    h.segments.push_back(3);
    for (int k = 0; k < 4; ++k)
      h.points.insert(h.points.end(), {dx + 0.01f * (s - 1), 0.03f - 0.01f * k, 0.0f});
  }
  writeCyHair(h, path);
}

// A refused CLI render: non-zero exit, one error line with every fragment, no output.
inline void expectCliRefused(const CommandResult& r, const std::vector<std::string>& fragments,
                             const std::string& dir) {
  SCOPED_TRACE(r.output);
  EXPECT_NE(r.exitCode, 0);
  const std::string line = onlyErrorLine(r.output);
  for (const std::string& f : fragments)
    EXPECT_NE(line.find(f), std::string::npos) << "lacks \"" << f << "\": " << line;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(e.path().extension(), e.path().filename() == "scene.json" ? ".json" : ".cage")
        << "written although refused: " << e.path();
}

}  // namespace clhair::test
