// test_scene_enums.cpp — the scene keys whose value is one of a few names (io/enum_field.h).
//
// Every name of every such key is read as the value it stands for (raster, quality, filter
// method, light type, key interpolation, children mode, up axis, camera preset), and a name
// that is none of them is refused with the exact error line the scene format has always
// given, in its own wording ("is ..., expected ..." or "must be ..., not ..."). Scenes are
// loaded without a device, a tiny hair mesh or the head strand file at most.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "clhair/error.h"
#include "clhair/scene.h"
#include "clhair/strand_groom.h"
#include "test_util.h"

namespace clhair::test {
namespace {

using nlohmann::json;

// Writes `scene` as dir/scene.json and returns its path.
std::string sceneFile(const std::string& dir, const json& scene) {
  const std::string path = dir + "/scene.json";
  std::ofstream(path) << scene.dump(2);
  return path;
}

json strandGroom(const json& extra) {
  json g = {{"strands_file", assetPath("grooms/head_bob.hair")}, {"max_strands", 8}};
  g.update(extra);
  return g;
}

TEST(SceneEnums, EveryNameReadsAsItsValue) {
  const std::string dir = scratchDir();
  auto load = [&](const json& scene) { return loadScene(sceneFile(dir, scene)); };

  EXPECT_EQ(load({{"raster", "lines"}}).raster, RasterMode::Lines);
  EXPECT_EQ(load({{"raster", "coverage"}}).raster, RasterMode::Coverage);

  EXPECT_EQ(load({{"quality", "draft"}}).quality.level, Quality::Draft);
  EXPECT_EQ(load({{"quality", "good"}}).quality.level, Quality::Good);
  EXPECT_EQ(load({{"quality", "final"}}).quality.level, Quality::Final);
  EXPECT_EQ(load({{"quality", {{"level", "good"}}}}).quality.level, Quality::Good);

  using Method = FilterParams::Method;
  EXPECT_EQ(load({{"filter", {{"method", "auto"}}}}).filter.method, Method::Auto);
  EXPECT_EQ(load({{"filter", {{"method", "lipp"}}}}).filter.method, Method::Lipp);
  EXPECT_EQ(load({{"filter", {{"method", "huang"}}}}).filter.method, Method::Huang);

  const Scene lights =
      load({{"lights", {{{"type", "point"}}, {{"type", "directional"}}, json::object()}}});
  ASSERT_EQ(lights.lights.size(), 3u);
  EXPECT_EQ(lights.lights[0].type, Light::Type::Point);
  EXPECT_EQ(lights.lights[1].type, Light::Type::Directional);
  EXPECT_EQ(lights.lights[2].type, Light::Type::Directional);  // the default

  for (const char* name : {"linear", "smooth"}) {
    const json camera = {{"preset", "mid"},
                         {"interpolation", name},
                         {"keys", {{{"frame", 1}}, {{"frame", 5}, {"azimuth", 40}}}}};
    EXPECT_EQ(load({{"camera", camera}}).cameraAnimation.keys.interpolation,
              std::string(name) == "linear" ? Interpolation::Linear : Interpolation::Smooth)
        << name;
  }

  using Mode = ChildrenParams::Mode;
  const Scene follow = load({{"grooms", {strandGroom({{"children", {{"mode", "follow"}}}})}}});
  const Scene interp =
      load({{"grooms", {strandGroom({{"children", {{"mode", "interpolated"}}}})}}});
  EXPECT_EQ(follow.grooms.at(0).strands->children.mode, Mode::Follow);
  EXPECT_EQ(interp.grooms.at(0).strands->children.mode, Mode::Interpolated);

  const struct {
    const char* name;
    UpAxis axis;
  } ups[] = {{"x", UpAxis::X}, {"y", UpAxis::Y}, {"z", UpAxis::Z}};
  for (const auto& up : ups) {
    const Scene s = load({{"grooms", {strandGroom({{"up", up.name}})}},
                          {"meshes", {{{"file", assetPath("meshes/head.obj")}, {"up", up.name}}}}});
    EXPECT_EQ(s.grooms.at(0).fileTransform, strandFileTransform(1.0f, up.axis)) << up.name;
    EXPECT_EQ(s.meshes.at(0).transform, strandFileTransform(1.0f, up.axis)) << up.name;
  }
  // the three axes place a file three different ways, so the checks above tell them apart
  EXPECT_NE(strandFileTransform(1.0f, UpAxis::X), strandFileTransform(1.0f, UpAxis::Y));
  EXPECT_NE(strandFileTransform(1.0f, UpAxis::Z), strandFileTransform(1.0f, UpAxis::Y));

  EXPECT_EQ(parseCameraPreset("close"), CameraPreset::Close);
  EXPECT_EQ(parseCameraPreset("mid"), CameraPreset::Mid);
  EXPECT_EQ(parseCameraPreset("far"), CameraPreset::Far);
}

TEST(SceneEnums, AnUnknownNameGetsTheSameLineAsEver) {
  const std::string dir = scratchDir();
  const std::string path = dir + "/scene.json";
  auto error = [&](const json& scene) {
    return errorOf([&] { loadScene(sceneFile(dir, scene)); });
  };
  const json keyed = {{"keys", {{{"frame", 1}}}}, {"interpolation", "cubic"}};

  EXPECT_EQ(error({{"raster", "dots"}}),
            path + ": raster: must be \"lines\" or \"coverage\", not \"dots\"");
  EXPECT_EQ(error({{"quality", "best"}}),
            path + ": quality: must be \"draft\", \"good\" or \"final\", not \"best\"");
  EXPECT_EQ(error({{"quality", {{"level", "ultra"}}}}),
            path + ": quality.level: must be \"draft\", \"good\" or \"final\", not \"ultra\"");
  EXPECT_EQ(error({{"filter", {{"method", "box"}}}}),
            path + ": filter.method: must be \"auto\", \"lipp\" or \"huang\", not \"box\"");
  EXPECT_EQ(error({{"lights", {{{"type", "spot"}}}}}),
            path + ": lights[0].type: is \"spot\", expected \"point\" or \"directional\"");
  EXPECT_EQ(error({{"grooms", {strandGroom({{"transform", keyed}})}}}),
            path +
                ": grooms[0].transform.interpolation: is \"cubic\", expected \"linear\" or "
                "\"smooth\"");
  EXPECT_EQ(error({{"grooms", {strandGroom({{"children", {{"mode", "guided"}}}})}}}),
            path +
                ": grooms[0].children.mode: is \"guided\", expected \"follow\" or "
                "\"interpolated\"");
  EXPECT_EQ(error({{"grooms", {strandGroom({{"up", "w"}})}}}),
            path + ": grooms[0].up: is \"w\", expected \"x\", \"y\" or \"z\"");
  EXPECT_EQ(error({{"meshes", {{{"file", assetPath("meshes/head.obj")}, {"up", "q"}}}}}),
            path + ": meshes[0].up: is \"q\", expected \"x\", \"y\" or \"z\"");
  EXPECT_EQ(error({{"camera", {{"preset", "near"}}}}),
            path + ": camera.preset: unknown camera preset \"near\"; expected close, mid or far");
  EXPECT_EQ(errorOf([] { parseCameraPreset("Close"); }),
            "unknown camera preset \"Close\"; expected close, mid or far");
}

}  // namespace
}  // namespace clhair::test
