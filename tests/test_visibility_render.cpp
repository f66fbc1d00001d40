// test_visibility_render.cpp — baked spherical visibility (Kulikov 2025, "precomputed
// self-shadowing") in rendered frames; the file format, the SH evaluation and the bake itself
// are in test_visibility.cpp.
//
//  VisibilityRender.*  strands deep in a slab render darker than the ones facing the light
//                      with the bake and alike without; the bake switched off gives the
//                      frame without a bake bit for bit; the CLI bakes, renders and refuses
//                      bad files with one line.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "cl/device_impl.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "clhair/visibility.h"
#include "clhair/visibility_sh.h"
#include "groom/visibility_bake.h"
#include "test_util.h"

namespace clhair {
namespace {

using test::readBytes;
using test::writeBytes;

// The slab as a scene: 1200 vertical strands in x in [-20, 20] mm, z in [-10, 10] mm with
// root uv from (x, z), one directional light from +x without a deep opacity map, the camera
// on the x axis at `cameraX` looking at the slab; no ambient light, black background.
Scene slabScene(std::shared_ptr<const VisibilityBake> bake, float cameraX = 0.12f) {
  StrandGroom g;
  g.name = "slab";
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> j(-0.3f, 0.3f);
  for (int a = 0; a < 40; ++a)
    for (int c = 0; c < 30; ++c) {
      const float x = -0.02f + 0.001f * (a + 0.5f + j(rng));
      const float z = -0.01f + (0.02f / 30.0f) * (c + 0.5f + j(rng));
      g.pointCounts.push_back(9);
      for (int k = 0; k < 9; ++k) g.points.emplace_back(x, -0.03f + 0.06f * k / 8.0f, z);
      g.rootUv.emplace_back((a + 0.5f) / 40.0f, (c + 0.5f) / 30.0f);
    }
  g.appearance.strandWidth = 2e-4f;
  Scene s;
  s.width = 96;
  s.height = 64;
  s.camera.position = glm::vec3(cameraX, 0.0f, 0.0f);
  s.camera.target = glm::vec3(0.0f);
  s.camera.fovYDegrees = 35.0f;
  s.ambient = glm::vec3(0.0f);
  s.background = glm::vec3(0.0f);
  Light l;
  l.type = Light::Type::Directional;
  l.direction = glm::vec3(1.0f, 0.0f, 0.0f);
  l.intensity = 3.0f;
  s.lights.push_back(l);
  GroomInstance gi("slab", std::make_shared<const StrandGroom>(std::move(g)));
  gi.visibility = std::move(bake);
  s.grooms.push_back(gi);
  return s;
}

// Mean luminance of `f` over the pixels where `mask` (the same view without the bake) is lit.
double meanOverHair(const Frame& f, const Frame& mask) {
  double sum = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < f.color.rgba.size() / 4; ++i) {
    const float* m = &mask.color.rgba[4 * i];
    if (0.2126 * m[0] + 0.7152 * m[1] + 0.0722 * m[2] <= 1e-3) continue;
    const float* p = &f.color.rgba[4 * i];
    sum += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    ++n;
  }
  EXPECT_GT(n, 100);
  return sum / std::max(n, 1);
}

std::shared_ptr<const VisibilityBake> bakeSlab(Renderer& r) {
  VisibilityBakeOptions o;
  o.raysPerPoint = 32;
  o.pointsPerCell = 2;
  const Scene s = slabScene(nullptr);
  return std::make_shared<const VisibilityBake>(bakeGroomVisibility(r, s, 0, o));
}

TEST(VisibilityRender, DeepStrandsDarkerThanLitSide) {
  // Lit from +x, no deep opacity map: without the bake nothing shadows the light. Seen from
  // +x, the face of the slab that faces the light keeps at least 90 % of its brightness with
  // the bake; seen from -x, the far face, whose light crosses 40 mm of strands, keeps at
  // most 30 %. The same views without the bake are the yardstick (they differ in the BSDF's
  // front and back lighting, which the ratios cancel).
  Renderer r(test::sharedDevice());
  const auto bake = bakeSlab(r);
  RenderOptions o;
  o.lod = Toggle::Off;
  o.filter = Toggle::Off;
  const Frame litNo = r.render(slabScene(nullptr, 0.12f), o);
  const Frame farNo = r.render(slabScene(nullptr, -0.12f), o);
  const double lit =
      meanOverHair(r.render(slabScene(bake, 0.12f), o), litNo) / meanOverHair(litNo, litNo);
  const double deep =
      meanOverHair(r.render(slabScene(bake, -0.12f), o), farNo) / meanOverHair(farNo, farNo);
  std::printf("slab: the bake keeps %.3f of the lit face and %.3f of the far face\n", lit, deep);
  EXPECT_GT(lit, 0.9);
  EXPECT_LE(lit, 1.0 + 1e-6);  // visibility never brightens
  EXPECT_LT(deep, 0.3);
}

TEST(VisibilityRender, OffIsBitIdenticalToNoBake) {
  Renderer r(test::sharedDevice());
  const auto bake = bakeSlab(r);
  RenderOptions o;
  o.lod = Toggle::Off;
  const Frame none = r.render(slabScene(nullptr), o);
  RenderOptions off = o;
  off.bakedVisibility = false;
  const Frame a = r.render(slabScene(bake), off);
  ASSERT_EQ(none.color.rgba.size(), a.color.rgba.size());
  EXPECT_EQ(std::memcmp(none.color.rgba.data(), a.color.rgba.data(),
                        none.color.rgba.size() * sizeof(float)),
            0);
  const Frame on = r.render(slabScene(bake), o);
  EXPECT_NE(std::memcmp(none.color.rgba.data(), on.color.rgba.data(),
                        none.color.rgba.size() * sizeof(float)),
            0);
}

TEST(VisibilityRender, CliBakesRendersAndRefusesBadFiles) {
  const std::string dir = test::scratchDir();
  const std::string groom = test::assetPath("grooms/tiny.hairmesh.json");
  const std::string scene = dir + "/scene.json";
  auto writeScene = [&](const std::string& vis) {
    std::ofstream(scene)
        << R"({"resolution": [64, 48], "camera": {"position": [0, 0.03, 0.12], )"
        << R"("target": [0, 0.02, 0]}, "lights": [{"type": "directional", )"
        << R"("direction": [1, 0.3, 0.2]}], "spheres": [{"center": [0, -0.02, 0], )"
        << R"("radius": 0.02}], "grooms": [{"file": ")" << groom << "\"" << vis << "}]}";
  };
  writeScene("");
  const std::string vis = dir + "/tiny.clhvis";
  const auto bake = test::runCli("bake-visibility " + test::quote(scene) + " -o " +
                                 test::quote(vis) + " --rays 8 --points-per-cell 1");
  ASSERT_EQ(bake.exitCode, 0) << bake.output;
  EXPECT_NE(bake.output.find("cells"), std::string::npos) << bake.output;
  writeScene(R"(, "visibility": {"file": ")" + vis + R"(", "absorption": 0.7})");
  const auto render =
      test::runCli("render " + test::quote(scene) + " -o " + test::quote(dir + "/out.png") + " -q");
  EXPECT_EQ(render.exitCode, 0) << render.output;
  // a truncated file, and a bake of another groom: one error line each, no image
  const std::string bytes = readBytes(vis);
  writeBytes(vis, bytes.substr(0, bytes.size() - 1));
  auto bad = test::runCli("render " + test::quote(scene) + " -o " + test::quote(dir + "/bad.png"));
  EXPECT_NE(bad.exitCode, 0);
  EXPECT_NE(test::onlyErrorLine(bad.output).find("is truncated"), std::string::npos) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/bad.png"));
  VisibilityBake other = readVisibility([&] {
    writeBytes(vis, bytes);
    return vis;
  }());
  other.strands += 1;
  writeVisibility(other, vis);
  bad = test::runCli("render " + test::quote(scene) + " -o " + test::quote(dir + "/bad.png"));
  EXPECT_NE(bad.exitCode, 0);
  EXPECT_NE(test::onlyErrorLine(bad.output).find("was baked for a groom of"), std::string::npos)
      << bad.output;
  writeScene("");
  const auto noGroom = test::runCli("bake-visibility " + test::quote(scene) + " -o " +
                                    test::quote(dir + "/x.clhvis") + " --groom 3");
  EXPECT_NE(noGroom.exitCode, 0);
  EXPECT_NE(test::onlyErrorLine(noGroom.output).find("does not exist"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.clhvis"));
  // the event cap and the study mode's options: one error line each, nothing written
  for (const std::string& args : {std::string("--max-events 0"), std::string("--max-events 33"),
                                  std::string("--transmittance-out ") +
                                      test::quote(dir + "/t.clhtrn") + " --directions per-cell"}) {
    const auto refused = test::runCli("bake-visibility " + test::quote(scene) + " -o " +
                                      test::quote(dir + "/x.clhvis") + " " + args);
    EXPECT_NE(refused.exitCode, 0) << args;
    EXPECT_NE(test::onlyErrorLine(refused.output).find("--"), std::string::npos) << refused.output;
    EXPECT_FALSE(std::filesystem::exists(dir + "/x.clhvis")) << args;
    EXPECT_FALSE(std::filesystem::exists(dir + "/t.clhtrn")) << args;
  }
  // the study mode writes a table of 4 absorptions x 64^3 cells x the rays' directions
  const auto study =
      test::runCli("bake-visibility " + test::quote(scene) + " -o " +
                   test::quote(dir + "/s.clhvis") + " --rays 8 --points-per-cell 1 " +
                   "--max-events 32 --transmittance-out " + test::quote(dir + "/s.clhtrn"));
  ASSERT_EQ(study.exitCode, 0) << study.output;
  const std::string table = readBytes(dir + "/s.clhtrn");
  ASSERT_EQ(table.size(), 20u + 4u * 4u + 4u * 4u * CLH_VIS_CELLS * 8u);
  EXPECT_EQ(table.substr(0, 8), "CLHTRN01");
  float t = 0.0f, most = 0.0f;
  for (std::size_t i = 36; i < table.size(); i += 4) {
    std::memcpy(&t, table.data() + i, 4);
    ASSERT_TRUE(t >= 0.0f && t <= 1.0f) << t;
    most = std::max(most, t);
  }
  EXPECT_GT(most, 0.5f);  // some cell sees open sky
}

}  // namespace
}  // namespace clhair
