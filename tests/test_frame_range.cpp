// test_frame_range.cpp — frame ranges of animated scenes, end to end through the CLI on the
// tiny groom at 64x48 (animation_scenes.h): bad ranges and keys are refused with one line;
// frames 7 and 53 are byte-identical rendered in one range, alone and in the reversed range
// (and differ from each other, so the animation is on), with and without reprojection and
// hair shadows under wind; zero wind, static keys and a cage animation holding the rest pose
// render every frame like the still scene; per-frame strand files render their own frames;
// --skip-existing keeps existing frames, a killed range leaves only complete frames and
// resumes, and no temporary file remains.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "animation_scenes.h"
#include "clhair/animation.h"
#include "test_util.h"

namespace clhair::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

TEST(FrameRange, CliRefusesBadRangesAndKeys) {
  const std::string dir = scratchDir();
  const std::string scene = writeScene(dir, tinyScene());
  expectCliRefused(runCli("render " + quote(scene) + " --frames 1-3 -o " + quote(dir + "/o.png")),
                   {"has no '#'", "3 frames"}, dir);
  expectCliRefused(
      runCli("render " + quote(scene) + " --frames 1-x -o " + quote(dir + "/o.##.png")),
      {"--frames \"1-x\"", "FIRST-LAST:STEP"}, dir);
  expectCliRefused(
      runCli("render " + quote(scene) + " --frames 1-9:0 -o " + quote(dir + "/o.##.png")),
      {"step must be at least 1"}, dir);
  const std::string unsorted =
      writeScene(dir, tinyScene({{"transform", {{"keys", {{{"frame", 9}}, {{"frame", 2}}}}}}}));
  expectCliRefused(
      runCli("render " + quote(unsorted) + " --frames 1-3 -o " + quote(dir + "/o.##.png")),
      {"grooms[0].transform.keys[1].frame", "increasing frame order"}, dir);
}

// ---- frame ranges end to end ------------------------------------------------------------

// Renders `frames` of `scene` to dir/<prefix>.####.exr and expects success.
void renderFrames(const std::string& scene, const std::string& frames, const std::string& dir,
                  const std::string& prefix, const std::string& extra = "") {
  const CommandResult r = runCli("render " + quote(scene) + " --frames " + frames + " -o " +
                                 quote(dir + "/" + prefix + ".####.exr") + " " + extra);
  ASSERT_EQ(r.exitCode, 0) << r.output;
}

// A scene in `dir` where everything animates at once: camera and transform keys, wind and a
// moving cage; returns its path.
std::string writeEverythingAnimated(const std::string& dir) {
  saveCageAnimation(restCage(60, 0.0005f), dir + "/moving.cage");
  const json groom = {
      {"transform",
       {{"interpolation", "smooth"},
        {"keys", {{{"frame", 1}, {"rotate_y", -20}}, {{"frame", 60}, {"rotate_y", 40}}}}}},
      {"cage_animation", {{"file", "moving.cage"}}},
      {"wind", {{"strength", 0.01}, {"direction", {1, 0, 0.5}}, {"frequency", 1}}}};
  const json camera = {
      {"keys", {{{"frame", 1}}, {{"frame", 60}, {"position", {0.05, 0.04, 0.2}}}}}};
  return writeScene(dir, tinyScene(groom, camera));
}

// Frames 7 and 53 of `scene` (CLI options `extra`) rendered in the range 3-55:2, alone and
// in the reversed range must be byte-identical; leaves range.####.exr in `dir`.
void expectRangeAloneAndReversedAgree(const std::string& scene, const std::string& dir,
                                      const std::string& extra) {
  renderFrames(scene, "3-55:2", dir, "range", extra);
  renderFrames(scene, "7", dir, "alone7", extra);
  renderFrames(scene, "53", dir, "alone53", extra);
  renderFrames(scene, "55-3:2", dir, "reversed", extra);
  for (const char* f : {"0007", "0053"}) {
    SCOPED_TRACE(f);
    const std::string a = readBytes(dir + "/range." + f + ".exr");
    ASSERT_GT(a.size(), 100u);
    EXPECT_TRUE(a == readBytes(dir + "/alone" + std::to_string(std::stoi(f)) + "." + f + ".exr"));
    EXPECT_TRUE(a == readBytes(dir + "/reversed." + f + ".exr"));
  }
}

TEST(FrameRange, FramesAreIdenticalInARangeAloneAndReversed) {
  const std::string dir = scratchDir();
  const std::string scene = writeEverythingAnimated(dir);
  expectRangeAloneAndReversedAgree(scene, dir, "");
  // the frames differ from each other: the animation reaches the image
  EXPECT_FALSE(readBytes(dir + "/range.0007.exr") == readBytes(dir + "/range.0053.exr"));
  EXPECT_FALSE(fs::exists(dir + "/range.0004.exr"));  // step 2 from 3: odd frames only
  EXPECT_TRUE(fs::exists(dir + "/range.0055.exr"));
}

TEST(FrameRange, FramesWithReprojectionAreIdenticalInARangeAloneAndReversed) {
  // the scene of the test above with temporal reprojection over 2 frames: each frame blends
  // frames it renders itself or holds from earlier in the same range, so it must not depend
  // on which frames the process rendered before
  const std::string dir = scratchDir();
  const std::string scene = writeEverythingAnimated(dir);
  expectRangeAloneAndReversedAgree(scene, dir, "--temporal 2");
  renderFrames(scene, "52-54", dir, "split", "--temporal 2");
  renderFrames(scene, "7", dir, "plain", "--temporal 0");
  EXPECT_TRUE(readBytes(dir + "/range.0053.exr") == readBytes(dir + "/split.0053.exr"));
  // the reprojection reaches the image
  EXPECT_FALSE(readBytes(dir + "/range.0007.exr") == readBytes(dir + "/plain.0007.exr"));
}

TEST(FrameRange, WindFramesWithHairShadowsAreIdenticalInARangeAndAlone) {
  // Wind moves the strands while the groom, its transform and the lights stay: the deep
  // opacity maps must follow the cage, or a frame rendered after another in one process
  // keeps that frame's hair shadows (frame 9 of a range from 1 differed from frame 9 alone).
  const std::string dir = scratchDir();
  json scene =
      tinyScene({{"wind", {{"strength", 0.02}, {"direction", {1, 0, 0.5}}, {"frequency", 1}}}});
  scene["lights"][0]["shadows"] = true;
  const std::string path = writeScene(dir, scene);
  renderFrames(path, "1-9:8", dir, "range");
  renderFrames(path, "9", dir, "alone");
  const std::string a = readBytes(dir + "/range.0009.exr");
  ASSERT_GT(a.size(), 100u);
  EXPECT_TRUE(a == readBytes(dir + "/alone.0009.exr"));
  EXPECT_FALSE(a == readBytes(dir + "/range.0001.exr")) << "the wind does not reach the image";
}

TEST(FrameRange, StaticAnimationRendersEveryFrameLikeTheStill) {
  const std::string dir = scratchDir();
  saveCageAnimation(restCage(4), dir + "/rest.cage");
  const std::string still = writeScene(dir, tinyScene(), "still.json");
  const json groom = {
      {"transform",
       {{"interpolation", "smooth"},
        {"keys", {{{"frame", 1}, {"rotate_y", 0}}, {{"frame", 4}, {"rotate_y", 0}}}}}},
      {"cage_animation", {{"file", "rest.cage"}}},
      {"wind", {{"strength", 0}, {"frequency", 3}}}};
  const json camera = {{"keys", {{{"frame", 1}}, {{"frame", 3}, {"fov", 35}}}}};
  const std::string animated = writeScene(dir, tinyScene(groom, camera), "animated.json");
  renderFrames(still, "1", dir, "still");
  renderFrames(animated, "1-5", dir, "anim");
  const std::string want = readBytes(dir + "/still.0001.exr");
  ASSERT_GT(want.size(), 100u);
  for (int f = 1; f <= 5; ++f)
    EXPECT_TRUE(readBytes(dir + "/anim.000" + std::to_string(f) + ".exr") == want)
        << "frame " << f << " differs from the still";
}

TEST(FrameRange, PerFrameStrandFilesRenderTheirOwnFrames) {
  const std::string dir = scratchDir();
  for (int f = 1; f <= 3; ++f)
    writeStrandFrame(dir + "/s." + std::to_string(f) + ".hair", 0.004f * static_cast<float>(f));
  json scene = tinyScene();
  scene["grooms"] = {{{"strands_file", "s.#.hair"},
                      {"appearance", {{"strand_width", 0.002}, {"min_hit_diameter_px", 1}}}}};
  const std::string path = writeScene(dir, scene);
  renderFrames(path, "1-3", dir, "range");
  renderFrames(path, "2", dir, "alone");
  const std::string second = readBytes(dir + "/range.0002.exr");
  EXPECT_TRUE(second == readBytes(dir + "/alone.0002.exr"));
  EXPECT_FALSE(second == readBytes(dir + "/range.0001.exr"));
  EXPECT_FALSE(second == readBytes(dir + "/range.0003.exr"));
}

TEST(FrameRange, SkipExistingKeepsFramesAndNoTemporaryRemains) {
  const std::string dir = scratchDir();
  const std::string scene =
      writeScene(dir, tinyScene({{"wind", {{"strength", 0.01}, {"frequency", 2}}}}), "scene.json");
  fs::create_directories(dir + "/out");
  renderFrames(scene, "1-3", dir + "/out", "f");
  const std::string second = readBytes(dir + "/out/f.0002.exr");
  ASSERT_GT(second.size(), 100u);
  writeText(dir + "/out/f.0001.exr", "kept");
  fs::remove(dir + "/out/f.0003.exr");
  const CommandResult r = runCli("render " + quote(scene) + " --frames 1-4 --skip-existing -o " +
                                 quote(dir + "/out/f.####.exr"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(readBytes(dir + "/out/f.0001.exr"), "kept");  // skipped, not re-rendered
  EXPECT_TRUE(readBytes(dir + "/out/f.0002.exr") == second);
  EXPECT_TRUE(fs::exists(dir + "/out/f.0003.exr"));
  EXPECT_TRUE(fs::exists(dir + "/out/f.0004.exr"));
  EXPECT_NE(r.output.find("frame 1 (1/4): "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("2 frames rendered, 2 skipped"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("frame 4 (4/4) -> "), std::string::npos) << r.output;
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir + "/out")) {
    ++files;
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos)
        << "temporary left behind: " << e.path();
  }
  EXPECT_EQ(files, 4u);
  // -q: nothing on either stream
  const CommandResult q =
      runCli("render " + quote(scene) + " --frames 5-6 -q -o " + quote(dir + "/out/f.####.exr"));
  EXPECT_EQ(q.exitCode, 0);
  EXPECT_EQ(q.output, "");
}

TEST(FrameRange, AKilledRangeLeavesOnlyCompleteFramesAndResumes) {
  const std::string dir = scratchDir();
  const std::string scene =
      writeScene(dir, tinyScene({{"wind", {{"strength", 0.01}, {"frequency", 2}}}}));
  fs::create_directories(dir + "/out");
  const std::string pattern = quote(dir + "/out/f.####.exr");
  // start a long range in the background and kill it hard once some frames are written
  const CommandResult started =
      runCommand(quote(cliPath()) + " render " + quote(scene) + " --frames 1-2000 -q -o " +
                 pattern + " >/dev/null 2>&1 & echo $!");
  const long pid = std::stol(started.output);
  auto finished = [&] {
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir + "/out"))
      n += e.path().filename().string().rfind(".tmp-", 0) != 0;
    return n;
  };
  for (int i = 0; i < 600 && finished() < 3; ++i) ::usleep(100000);
  runCommand("kill -9 " + std::to_string(pid));
  for (int i = 0; i < 50 && runCommand("kill -0 " + std::to_string(pid)).exitCode == 0; ++i)
    ::usleep(100000);
  ASSERT_GE(finished(), 3u) << "the range wrote no frames in 60 s";
  // every file under a frame's name is complete: the frame exactly as rendered alone
  std::vector<std::string> frames;
  for (const auto& e : fs::directory_iterator(dir + "/out"))
    if (e.path().filename().string().rfind(".tmp-", 0) != 0) frames.push_back(e.path().string());
  std::sort(frames.begin(), frames.end());
  const std::string last = frames.back();
  const std::string number = last.substr(last.size() - 8, 4);
  renderFrames(scene, std::to_string(std::stoi(number)), dir, "alone");
  EXPECT_TRUE(readBytes(last) == readBytes(dir + "/alone." + number + ".exr"))
      << last << " is not the complete frame";
  // resuming renders only what is missing; a stale temporary does not count as a frame
  const std::size_t before = frames.size();
  const CommandResult r = runCli("render " + quote(scene) + " --frames 1-" +
                                 std::to_string(before + 2) + " --skip-existing -o " + pattern);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("2 frames rendered, " + std::to_string(before) + " skipped"),
            std::string::npos)
      << r.output;
}

}  // namespace
}  // namespace clhair::test
