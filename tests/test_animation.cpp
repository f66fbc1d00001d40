// test_animation.cpp — animated scenes (the frame ranges end to end: test_frame_range.cpp).
//
// Keyframes: KeyTrack against values computed by hand (linear, smooth = Hermite with
// Catmull-Rom inner tangents and zero end tangents), clamped before the first and after the
// last key; sceneAtFrame's groom transform and wind against the formulas of
// docs/scene-format.md; a cage update reuses the device groom and matches a rebuild. Files:
// the cage-animation reader round-trips and refuses malformed files with one line; scenes
// with bad keys or a cage that disagrees with its groom are refused by the CLI with one error
// line and no output.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "animation_scenes.h"
#include "clhair/animation.h"
#include "clhair/error.h"
#include "clhair/hair_mesh.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "groom/groom_cache.h"
#include "groom/hair_mesh_gpu.h"
#include "groom_stages.h"
#include "io/cyhair.h"
#include "test_util.h"

namespace clhair::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

KeyTrack track(Interpolation interp, std::vector<double> frames, std::vector<double> values) {
  KeyTrack t;
  t.interpolation = interp;
  t.width = 1;
  t.frames = std::move(frames);
  t.values = std::move(values);
  return t;
}

double at(const KeyTrack& t, double frame) { return t.evaluate(frame)[0]; }

TEST(Keyframes, LinearInterpolatesAndClamps) {
  const KeyTrack t = track(Interpolation::Linear, {1, 11, 21}, {0, 10, 4});
  EXPECT_DOUBLE_EQ(at(t, 1), 0.0);
  EXPECT_DOUBLE_EQ(at(t, 6), 5.0);
  EXPECT_DOUBLE_EQ(at(t, 11), 10.0);
  EXPECT_DOUBLE_EQ(at(t, 16), 7.0);    // 10 + (4 - 10) * 0.5
  EXPECT_DOUBLE_EQ(at(t, 13.5), 8.5);  // 10 - 6 * 0.25
  EXPECT_DOUBLE_EQ(at(t, -100), 0.0);  // before the first key
  EXPECT_DOUBLE_EQ(at(t, 1000), 4.0);  // after the last key
}

TEST(Keyframes, SmoothWithTwoKeysIsSmoothstep) {
  const KeyTrack t = track(Interpolation::Smooth, {0, 4}, {0, 10});
  EXPECT_NEAR(at(t, 1), 10 * 0.15625, 1e-12);  // 3u^2 - 2u^3 at u = 0.25
  EXPECT_NEAR(at(t, 2), 5.0, 1e-12);
  EXPECT_NEAR(at(t, 3), 10 * 0.84375, 1e-12);
  EXPECT_DOUBLE_EQ(at(t, -1), 0.0);
  EXPECT_DOUBLE_EQ(at(t, 9), 10.0);
}

TEST(Keyframes, SmoothUsesCatmullRomTangentsAtInnerKeys) {
  // keys (0, 0), (2, 4), (6, 10): the inner tangent is (10 - 0) / (6 - 0) = 5/3 per frame
  const KeyTrack t = track(Interpolation::Smooth, {0, 2, 6}, {0, 4, 10});
  // frame 1: u = 0.5, h = 2: 0.5 * 0 + 0.125 * 2 * 0 + 0.5 * 4 - 0.125 * 2 * 5/3
  EXPECT_NEAR(at(t, 1), 2.0 - 0.25 * 5.0 / 3.0, 1e-12);
  // frame 4: u = 0.5, h = 4: 0.5 * 4 + 0.125 * 4 * 5/3 + 0.5 * 10 - 0.125 * 4 * 0
  EXPECT_NEAR(at(t, 4), 7.0 + 0.5 * 5.0 / 3.0, 1e-12);
  EXPECT_DOUBLE_EQ(at(t, 2), 4.0);  // passes through every key
  EXPECT_DOUBLE_EQ(at(t, 6), 10.0);
  EXPECT_DOUBLE_EQ(at(t, 7), 10.0);
  // the same keys linear differ between keys: the smooth curve is really used
  EXPECT_GT(std::fabs(at(t, 1) - at(track(Interpolation::Linear, {0, 2, 6}, {0, 4, 10}), 1)), 0.1);
}

TEST(Keyframes, SeveralValuesPerKey) {
  KeyTrack t;
  t.width = 2;
  t.frames = {0, 10};
  t.values = {0, 100, 1, 200};
  const std::vector<double> v = t.evaluate(2.5);
  ASSERT_EQ(v.size(), 2u);
  EXPECT_DOUBLE_EQ(v[0], 0.25);
  EXPECT_DOUBLE_EQ(v[1], 125.0);
}

// ---- scenes ---------------------------------------------------------------------------------

// The error text of loading `scene` (empty when it loads).
std::string loadError(const std::string& dir, const json& scene) {
  return errorOf([&] { loadScene(writeScene(dir, scene)); });
}

TEST(AnimatedScene, BadKeysAreRefusedWithOneLine) {
  const std::string dir = scratchDir();
  struct Case {
    const char* groom;   // added to the groom entry (JSON object text)
    const char* camera;  // added to the camera
    std::vector<std::string> fragments;
  };
  const std::vector<Case> cases = {
      {R"({"transform": {"keys": [{"frame": 5}, {"frame": 3}]}})",
       "{}",
       {"grooms[0].transform.keys[1].frame", "is 3", "increasing frame order"}},
      {R"({"transform": {"keys": [{"frame": 5}, {"frame": 5}]}})",
       "{}",
       {"keys[1].frame", "not after the previous key's 5"}},
      {R"({"transform": {"keys": [{"frame": 1}, {"rotate_y": 9}]}})",
       "{}",
       {"keys[1].frame", "is missing"}},
      {R"({"transform": {"keys": [{"frame": 1, "rotate": 9}]}})",
       "{}",
       {"keys[0].rotate", "not a known key"}},
      {R"({"transform": {"keys": [{"frame": 1, "scale": 0}]}})",
       "{}",
       {"keys[0].scale", "is 0, expected"}},
      {R"({"transform": {"keys": []}})", "{}", {"transform.keys", "non-empty array"}},
      {R"({"transform": {"keys": [{"frame": 1}], "interpolation": "cubic"}})",
       "{}",
       {"transform.interpolation", "\"cubic\"", "\"smooth\""}},
      {R"({"transform": {"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], "keys": [{"frame": 1}]}})",
       "{}",
       {"transform.keys", "matrix"}},
      {"{}",
       R"({"keys": [{"frame": 1, "position": [0, 0.025, 0]}]})",
       {"camera.keys[0]", "target must differ from position"}},
      {"{}", R"({"keys": [{"frame": "one"}]})", {"camera.keys[0].frame", "must be a number"}},
      {"{}", R"({"keys": [{"frame": 1e300}]})", {"camera.keys[0].frame", "expected"}},
      {"{}", R"({"keys": [{"frame": 1, "fov": 200}]})", {"camera.keys[0].fov", "expected 1..170"}},
      {R"({"wind": {"strength": 0.1, "direction": [0, 0, 0]}})",
       "{}",
       {"grooms[0].wind.direction", "must not be zero"}},
      {R"({"wind": {"strength": -1}})", "{}", {"grooms[0].wind.strength", "is -1"}},
      {R"({"wind": {"gust": 1}})", "{}", {"grooms[0].wind.gust", "not a known key"}},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE("case " + std::to_string(i));
    const std::string err =
        loadError(dir, tinyScene(json::parse(cases[i].groom), json::parse(cases[i].camera)));
    ASSERT_FALSE(err.empty()) << "the scene loaded";
    EXPECT_EQ(err.find('\n'), std::string::npos) << err;
    EXPECT_NE(err.find("scene.json"), std::string::npos) << err;
    for (const std::string& f : cases[i].fragments)
      EXPECT_NE(err.find(f), std::string::npos) << "lacks \"" << f << "\": " << err;
  }
}

TEST(AnimatedScene, TransformKeysGiveTheGroomsTransformPerFrame) {
  const std::string dir = scratchDir();
  const json groom = {{"transform",
                       {{"translate", {0.0, 0.5, 0.0}},
                        {"keys",
                         {{{"frame", 1}, {"rotate_y", 0}, {"translate", {0.0, 0.0, 0.0}}},
                          {{"frame", 11}, {"rotate_y", 90}, {"scale", 3}}}}}}};
  const Scene scene = loadScene(writeScene(dir, tinyScene(groom)));
  EXPECT_TRUE(isAnimated(scene));
  // frame 6, linear: translate halfway from (0, 0, 0) to the still (0, 0.5, 0), 45 degrees,
  // scale halfway from the still 1 to 3
  const Scene s6 = sceneAtFrame(scene, 6.0);
  glm::mat4 want = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.25f, 0.0f));
  want = glm::rotate(want, glm::radians(45.0f), glm::vec3(0, 1, 0));
  want = glm::scale(want, glm::vec3(2.0f));
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      EXPECT_NEAR(s6.grooms[0].transform[c][r], want[c][r], 1e-6f) << c << "," << r;
  // after the last key: the last key's values
  const Scene s99 = sceneAtFrame(scene, 99.0);
  EXPECT_NEAR(s99.grooms[0].transform[3][1], 0.5f, 1e-6f);
  EXPECT_NEAR(glm::length(glm::vec3(s99.grooms[0].transform[0])), 3.0f, 1e-5f);
}

TEST(AnimatedScene, StrandFileKeysApplyAfterTheFilesScaleAndUpAxis) {
  const std::string dir = scratchDir();
  const json scene = {
      {"grooms",
       {{{"strands_file", assetPath("grooms/head_bob.hair")},
         {"scale", 0.01},
         {"up", "z"},
         {"transform",
          {{"keys", {{{"frame", 0}}, {{"frame", 10}, {"translate", {1.0, 0.0, 0.0}}}}}}}}}}};
  const Scene s = loadScene(writeScene(dir, scene));
  const Scene mid = sceneAtFrame(s, 5.0);
  // the file's transform (scale 0.01, z up) is kept: the keyed translation comes on top
  const glm::mat4 want =
      glm::translate(glm::mat4(1.0f), glm::vec3(0.5f, 0.0f, 0.0f)) * s.grooms[0].transform;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) EXPECT_NEAR(mid.grooms[0].transform[c][r], want[c][r], 1e-6f);
  EXPECT_FALSE(mid.grooms[0].deformed);  // strand files have no cage
}

TEST(AnimatedScene, PerFrameStrandFilesAreReadPerFrameAndHeldOutsideTheirRange) {
  const std::string dir = scratchDir();
  writeStrandFrame(dir + "/s.0002.hair", 0.0f);
  writeStrandFrame(dir + "/s.0003.hair", 0.004f);
  writeStrandFrame(dir + "/s.0005.hair", 0.008f);
  writeStrandFrame(dir + "/s.05.hair", 1.0f);  // another padding: not part of the sequence
  const json scene = {{"grooms", {{{"strands_file", "s.####.hair"}, {"name", "seq"}}}}};
  const Scene s = loadScene(writeScene(dir, scene));
  ASSERT_TRUE(s.grooms[0].strandFrames);
  EXPECT_EQ(s.grooms[0].strandFrames->first, 2);
  EXPECT_EQ(s.grooms[0].strandFrames->last, 5);
  auto firstX = [](const Scene& f) { return f.grooms[0].strands->points[4].x; };  // strand 1
  EXPECT_FLOAT_EQ(firstX(s), 0.0f);
  EXPECT_FLOAT_EQ(firstX(sceneAtFrame(s, 3)), 0.004f);
  EXPECT_FLOAT_EQ(firstX(sceneAtFrame(s, 2.6)), 0.004f);  // the nearest whole frame
  EXPECT_FLOAT_EQ(firstX(sceneAtFrame(s, 9)), 0.008f);    // held after the last
  EXPECT_FLOAT_EQ(firstX(sceneAtFrame(s, -4)), 0.0f);     // and before the first
  // a frame inside the range without a file: one line naming the groom, frame and file
  const std::string err = errorOf([&] { sceneAtFrame(s, 4); });
  EXPECT_NE(err.find("groom \"seq\" at frame 4"), std::string::npos) << err;
  EXPECT_NE(err.find("s.0004.hair"), std::string::npos) << err;
  EXPECT_EQ(err.find('\n'), std::string::npos) << err;
  // a pattern that matches nothing
  const std::string none = loadError(dir, {{"grooms", {{{"strands_file", "t.###.hair"}}}}});
  EXPECT_NE(none.find("no file matches"), std::string::npos) << none;
}

TEST(AnimatedScene, CameraKeysInterpolatePositionAndFov) {
  const std::string dir = scratchDir();
  const json camera = {
      {"interpolation", "smooth"},
      {"keys", {{{"frame", 0}}, {{"frame", 4}, {"position", {0.4, 0.03, 0.2}}, {"fov", 45}}}}};
  const Scene scene = loadScene(writeScene(dir, tinyScene(json::object(), camera)));
  const Scene s1 = sceneAtFrame(scene, 1.0);
  EXPECT_NEAR(s1.camera.position.x, 0.4 * 0.15625, 1e-6);  // smoothstep at u = 0.25
  EXPECT_NEAR(s1.camera.fovYDegrees, 35.0 + 10.0 * 0.15625, 1e-5);
  EXPECT_NEAR(s1.camera.target.y, 0.025f, 1e-7f);  // not keyed: the still value
  EXPECT_NEAR(sceneAtFrame(scene, -3.0).camera.position.x, 0.0f, 1e-7f);
}

TEST(AnimatedScene, WindMovesTipsByTheDocumentedAmountAndKeepsRoots) {
  const std::string dir = scratchDir();
  const json groom = {{"wind",
                       {{"strength", 0.02},
                        {"direction", {0, 0, 2}},
                        {"frequency", 0.5},
                        {"wavelength", 1e6}}}};  // one phase for every root
  json scene = tinyScene(groom);
  scene["frame_rate"] = 2;
  const Scene s = loadScene(writeScene(dir, scene));
  const HairMesh& m = *s.grooms[0].mesh;
  const int L = m.layerCount, V = m.vertexCount;
  // frame 1 = 0.5 s: sin(2 pi * 0.5 * 0.5) = 1, the full lean; roots x = 0 keep phase 0
  for (double frame : {1.0, 3.0}) {
    const Scene f = sceneAtFrame(s, frame);
    ASSERT_TRUE(f.grooms[0].deformed);
    const std::vector<glm::vec3>& p = *f.grooms[0].deformed;
    const double gust = 0.5 + 0.5 * std::sin(2.0 * M_PI * 0.5 * frame / 2.0);
    for (int v = 0; v < V; ++v) {
      EXPECT_EQ(p[v], m.positions[v]) << "root " << v << " moved";
      for (int l = 1; l < L; ++l) {
        const std::size_t i = static_cast<std::size_t>(l) * V + v;
        const float h = static_cast<float>(l) / static_cast<float>(L - 1);
        const glm::vec3 d = p[i] - m.positions[i];
        EXPECT_NEAR(d.x, 0.0f, 1e-7f);
        EXPECT_NEAR(d.y, 0.0f, 1e-7f);
        EXPECT_NEAR(d.z, 0.02 * h * h * gust, 2e-6) << "frame " << frame << " layer " << l;
      }
    }
  }
}

TEST(AnimatedScene, CageUpdatesReuseTheDeviceGroomAndMatchARebuild) {
  const std::string dir = scratchDir();
  HairMesh mesh = loadHairMesh(assetPath("grooms/tiny.hairmesh.json"));
  mesh.ao.assign(mesh.positions.size(), 1.0f);  // no AO bake
  const std::string meshPath = dir + "/tiny.hairmesh.json";
  saveHairMesh(mesh, meshPath);
  const Scene scene = loadScene(writeScene(
      dir,
      tinyScene({{"file", meshPath},
                 {"wind", {{"strength", 0.02}, {"direction", {1, 0, 0}}, {"frequency", 3}}}})));
  GroomStagesOnDevice st;
  GroomCache cache(st.stages);
  GroomGpu* first = nullptr;
  std::uint64_t bytes = 0;
  std::vector<float> tipsX;
  for (int frame = 1; frame <= 4; ++frame) {
    SCOPED_TRACE("frame " + std::to_string(frame));
    const Scene still = sceneAtFrame(scene, frame);
    cache.beginFrame();
    GroomGpu& g = cache.get(still.grooms[0]);
    if (!first) {
      first = &g;
      bytes = g.deviceBytes();
    }
    // one device form for the whole shot: same object, same buffers, no growth
    EXPECT_EQ(&g, first);
    EXPECT_EQ(cache.size(), 1u);
    EXPECT_EQ(g.deviceBytes(), bytes);
    // its strands are those of a hair mesh built from this frame's cage
    const StrandSet got = g.exportStrands(1.0f);
    HairMesh moved = mesh;
    moved.positions = *still.grooms[0].deformed;
    HairMeshGpu fresh(std::make_shared<const HairMesh>(moved), st.stages, false);
    const StrandSet want = fresh.exportStrands(1.0f);
    ASSERT_EQ(got.pointCounts, want.pointCounts);
    EXPECT_TRUE(got.points == want.points);
    EXPECT_TRUE(got.tangents == want.tangents);
    tipsX.push_back(got.points[3 * (got.pointCounts[0] - 1)]);
    cache.trim();
  }
  EXPECT_NE(tipsX[0], tipsX[1]);  // the wind reached the strands
  // back at rest: the rest pose's strands again
  cache.beginFrame();
  HairMeshGpu rest(std::make_shared<const HairMesh>(mesh), st.stages, false);
  EXPECT_TRUE(cache.get(scene.grooms[0]).exportStrands(1.0f).points ==
              rest.exportStrands(1.0f).points);
  // two instances of one mesh deformed differently in one frame share buffers: refused
  Scene two = sceneAtFrame(scene, 2);
  two.grooms.push_back(sceneAtFrame(scene, 3).grooms[0]);
  Renderer renderer(sharedDevice());
  try {
    renderer.render(two);
    ADD_FAILURE() << "two differently deformed instances of one mesh were drawn";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("deformed differently"), std::string::npos) << e.what();
  }
  // the same cage twice is fine
  Scene same = sceneAtFrame(scene, 2);
  same.grooms.push_back(same.grooms[0]);
  EXPECT_NO_THROW(renderer.render(same));
}

// ---- cage-animation files -----------------------------------------------------------------

TEST(CageFile, RoundTrips) {
  const std::string dir = scratchDir();
  const CageAnimation c = restCage(3, 0.01f);
  saveCageAnimation(c, dir + "/a.cage");
  EXPECT_EQ(fs::file_size(dir + "/a.cage"), 24u + 12u * c.positions.size());
  const CageAnimation r = loadCageAnimation(dir + "/a.cage", 1ull << 30);
  EXPECT_EQ(r.frames, 3u);
  EXPECT_EQ(r.vertices, c.vertices);
  EXPECT_EQ(r.positions, c.positions);
}

TEST(CageFile, MalformedFilesAreRefusedWithOneLine) {
  const std::string dir = scratchDir();
  const std::string good = dir + "/good.cage";
  saveCageAnimation(restCage(2), good);
  const std::string bytes = readBytes(good);
  auto patched = [&](std::size_t offset, std::uint32_t v) {
    std::string b = bytes;
    for (int i = 0; i < 4; ++i) b[offset + i] = static_cast<char>((v >> (8 * i)) & 0xFF);
    return b;
  };
  std::string nan = bytes;
  const std::uint32_t qnan = 0x7fc00000u;
  for (int i = 0; i < 4; ++i)
    nan[24 + 12 * 30 + 4 + i] = static_cast<char>((qnan >> (8 * i)) & 0xFF);
  struct Case {
    std::string data;
    std::vector<std::string> fragments;
  };
  const std::vector<Case> cases = {
      {bytes.substr(0, bytes.size() - 5), {"truncated", "header says 2 frames of 28 vertices"}},
      {bytes.substr(0, 10), {"truncated", "shorter than the 24-byte header"}},
      {bytes + "xx", {"wrong size"}},
      {"CLHCAGX" + bytes.substr(7), {"not a cage-animation file"}},
      {patched(8, 2), {"version 2"}},
      {patched(12, 0), {"0 frames"}},
      {patched(16, 0xFFFFFFFFu), {"4294967295 vertices"}},
      {patched(12, kMaxCageFrames), {"truncated", "1000000 frames of 28 vertices"}},
      {patched(20, 7), {"reserved"}},
      {nan, {"frame 1, vertex 2", "non-finite", "nan"}},
      {"", {"truncated"}},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE("case " + std::to_string(i));
    const std::string path = dir + "/bad" + std::to_string(i) + ".cage";
    writeText(path, cases[i].data);
    const std::string err = errorOf([&] { loadCageAnimation(path, 1ull << 30); });
    ASSERT_FALSE(err.empty()) << "the file was accepted";
    EXPECT_EQ(err.find('\n'), std::string::npos) << err;
    EXPECT_NE(err.find(path), std::string::npos) << err;
    for (const std::string& f : cases[i].fragments)
      EXPECT_NE(err.find(f), std::string::npos) << "lacks \"" << f << "\": " << err;
  }
  // over the byte limit: refused before the positions are read
  const std::string err = errorOf([&] { loadCageAnimation(good, 100); });
  EXPECT_NE(err.find("over the limit"), std::string::npos) << err;
}

TEST(CageFile, CliRefusesACageThatDisagreesWithTheGroom) {
  const std::string dir = scratchDir();
  CageAnimation c = restCage(2);
  c.vertices = 7;  // the root layer only
  c.positions.resize(14);
  saveCageAnimation(c, dir + "/short.cage");
  const std::string scene =
      writeScene(dir, tinyScene({{"cage_animation", {{"file", "short.cage"}}}}));
  expectCliRefused(
      runCli("render " + quote(scene) + " --frames 1-2 -o " + quote(dir + "/out.####.png")),
      {"grooms[0].cage_animation.file", "holds 7 vertices per frame",
       "the groom's cage has 28 (4 layers of 7 vertices)"},
      dir);
  const std::string truncated = dir + "/short.cage";
  writeText(truncated, readBytes(truncated).substr(0, 40));
  expectCliRefused(
      runCli("render " + quote(scene) + " --frames 1-2 -o " + quote(dir + "/out.####.png")),
      {"short.cage", "truncated"}, dir);
}

}  // namespace
}  // namespace clhair::test
