// test_frame_passes.cpp — frames built as graphs (host/passes/): the passes each option set
// produces, the host waits of a steady-state frame (exactly one: its read-back), every pass
// binding only what it declared (the graph's checks on), and frames in flight equal to
// frames rendered one at a time, through the library and through `clhair render --frames`.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>

#include "cl/device_impl.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "test_util.h"

namespace clhair::test {
namespace {

namespace fs = std::filesystem;

// The graph's declaration checks on for the shared device while alive.
struct GraphChecks {
  bool before;
  GraphChecks() : before(sharedDevice().impl()->graphChecks) {
    sharedDevice().impl()->graphChecks = true;
  }
  ~GraphChecks() { sharedDevice().impl()->graphChecks = before; }
};

// A shipped scene made small: 64x36 pixels, 64x64 shadow maps.
Scene smallScene(const std::string& name) {
  Scene s = loadScene(assetPath("scenes/" + name));
  s.width = 64;
  s.height = 36;
  s.shadows.resolution = 64;
  return s;
}

// The passes that ran, from Frame::passes ("  N. name" lines; culled ones are marked).
std::vector<std::string> passNames(const std::string& graph) {
  std::vector<std::string> out;
  std::istringstream in(graph);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("  ", 0) != 0 || line.size() < 4 || !std::isdigit(line[2])) continue;
    const std::size_t dot = line.find(". ");
    if (dot != std::string::npos) out.push_back(line.substr(dot + 2));
  }
  return out;
}

std::vector<std::string> groomPasses(std::size_t k, bool huang) {
  const std::string n = std::to_string(k);
  if (huang) return {"strands " + n, "link " + n, "shade " + n, "alpha fix " + n, "composite " + n};
  return {"strands " + n, "shade " + n, "composite " + n};
}

std::vector<std::string> concat(std::vector<std::vector<std::string>> parts) {
  std::vector<std::string> out;
  for (auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

// The shadow passes of a frame that builds the maps of `lights` (indices into the scene's).
std::vector<std::string> shadowPasses(std::initializer_list<int> lights) {
  std::vector<std::string> out = {"shadow maps"};
  for (int l : lights) out.push_back("shadow map: light " + std::to_string(l));
  out.push_back("shadow maps: the lights' records");
  return out;
}

struct Rendered {
  std::vector<std::string> first, second;  // the passes of two frames in a row
  std::uint64_t secondWaits = 0;
};

// Two frames in a row (one when `frames` is 1: the first's passes only).
Rendered twoFrames(const Scene& s, RenderOptions o, const std::vector<Camera>& cameras = {},
                   int frames = 2) {
  GraphChecks checks;
  Renderer r(sharedDevice());
  o.describePasses = true;
  Rendered out;
  auto one = [&]() { return cameras.empty() ? r.render(s, o) : r.renderViews(s, cameras, o)[0]; };
  const Frame a = one();
  out.first = passNames(a.passes);
  if (frames < 2) return out;
  const Frame b = one();
  out.second = passNames(b.passes);
  out.secondWaits = b.stats.hostWaits;
  return out;
}

// The tiny groom under one shadowed light (the option sets' pass lists do not depend on the
// groom's size), blown by wind or still.
std::string windScene(const std::string& dir, bool wind = true);
Scene tinyScene() { return loadScene(windScene(scratchDir(), false)); }

TEST(FramePasses, TheDefaultSceneRunsItsPassesAndWaitsOnceInASteadyFrame) {
  RenderOptions o;
  o.lod = Toggle::On;
  const Rendered d = twoFrames(smallScene("default.json"), o);
  EXPECT_EQ(d.first, concat({shadowPasses({0, 1, 2}),
                             {"opaque", "lod 0", "segment budget"},
                             groomPasses(0, true),
                             {"read-back"}}));
  // the maps are kept: the second frame has no shadow pass, and one host wait
  EXPECT_EQ(d.second,
            concat({{"opaque", "lod 0", "segment budget"}, groomPasses(0, true), {"read-back"}}));
  EXPECT_EQ(d.secondWaits, 1u);
}

TEST(FramePasses, MsaaNoFilterAndLippsFilterRunTheirPasses) {
  const Scene s = tinyScene();
  const std::vector<std::string> head =
      concat({shadowPasses({0}), {"opaque", "lod 0", "segment budget"}});
  RenderOptions o;
  o.msaa = 4;
  EXPECT_EQ(twoFrames(s, o, {}, 1).first, concat({head, groomPasses(0, false), {"read-back"}}));
  o.msaa = 1;
  o.filter = Toggle::Off;
  EXPECT_EQ(twoFrames(s, o, {}, 1).first, concat({head, groomPasses(0, false), {"read-back"}}));
  o.filter = Toggle::On;
  o.filterMethod = FilterParams::Method::Lipp;  // Lipp's
  EXPECT_EQ(twoFrames(s, o, {}, 1).first,
            concat({head, {"strands 0", "shade 0", "filter 0", "composite 0", "read-back"}}));
}

// Quality good with point shading (--shading point): the groom is shaded once per visible
// strand point (point_passes.cpp) in place of the per-sample shading pass, with no filter,
// and the frame still waits once.
TEST(FramePasses, PointShadingReplacesTheShadePassAndWaitsOnce) {
  const Scene s = smallScene("default.json");
  RenderOptions o;
  o.lod = Toggle::On;
  o.quality = Quality::Good;
  o.pointShading = Toggle::On;
  const Rendered d = twoFrames(s, o);
  const std::vector<std::string> groom = {"strands 0", "point marks 0", "point inputs 0",
                                          "shade points 0", "composite 0"};
  EXPECT_EQ(
      d.first,
      concat(
          {shadowPasses({0, 1, 2}), {"opaque", "lod 0", "segment budget"}, groom, {"read-back"}}));
  EXPECT_EQ(d.second, concat({{"opaque", "lod 0", "segment budget"}, groom, {"read-back"}}));
  EXPECT_EQ(d.secondWaits, 1u);
}

TEST(FramePasses, AllAovsAddTheirPassesAndStillWaitOnce) {
  const Scene s = tinyScene();
  RenderOptions o;
  o.aovs = true;
  o.strandIds = true;
  o.previous = &s;
  const Rendered d = twoFrames(s, o);
  EXPECT_EQ(d.first, concat({shadowPasses({0}),
                             {"opaque", "aov begin", "lod 0", "segment budget"},
                             groomPasses(0, true),
                             {"aov 0", "read-back"}}));
  EXPECT_EQ(d.secondWaits, 1u);
}

TEST(FramePasses, TwoViewsShareOneStrandPassAndWaitOnce) {
  const Scene s = tinyScene();
  Camera side = s.camera;
  side.position.x += 0.01f;
  const Rendered d = twoFrames(s, RenderOptions{}, {s.camera, side});
  std::vector<std::string> want =
      concat({shadowPasses({0}), {"opaque, view 0", "opaque, view 1", "strands 0, all views"}});
  for (const char* v : {"0", "1"})
    for (const char* p : {"shade 0, view ", "filter 0, view ", "composite 0, view "})
      want.push_back(std::string(p) + v);
  want.push_back("record 0");
  want.push_back("read-back");
  EXPECT_EQ(d.first, want);
  EXPECT_EQ(d.secondWaits, 1u);
}

// The passes of view `v` in a frame of several views, without their ", view v".
std::vector<std::string> passesOfView(const std::vector<std::string>& all, std::size_t v) {
  const std::string suffix = ", view " + std::to_string(v);
  std::vector<std::string> out;
  for (const std::string& p : all)
    if (p.size() > suffix.size() && p.compare(p.size() - suffix.size(), suffix.size(), suffix) == 0)
      out.push_back(p.substr(0, p.size() - suffix.size()));
  return out;
}

// One graph builder for any number of views: each view of a frame of several gets the passes
// a frame of that view alone gets, less those of the frame (shadow maps, read-back) and the
// groom's LOD, segment budget and strands, which several views draw once for all of them.
TEST(FramePasses, SeveralViewsAndOneViewBuildTheSamePassesPerView) {
  const Scene s = tinyScene();
  Camera side = s.camera;
  side.position.x += 0.01f;
  const std::vector<std::string> once = {"lod 0", "segment budget", "strands 0", "read-back"};
  for (const int msaa : {1, 4}) {
    RenderOptions o;
    o.msaa = msaa;
    o.filterMethod = FilterParams::Method::Lipp;  // several views refuse Huang's
    std::vector<std::string> alone;
    for (const std::string& p : twoFrames(s, o, {}, 1).first)
      if (p.rfind("shadow map", 0) != 0 && std::find(once.begin(), once.end(), p) == once.end())
        alone.push_back(p);
    ASSERT_FALSE(alone.empty());
    const std::vector<std::string> both = twoFrames(s, o, {s.camera, side}, 1).first;
    for (std::size_t v = 0; v < 2; ++v)
      EXPECT_EQ(passesOfView(both, v), alone) << "MSAA " << msaa << ", view " << v;
    EXPECT_EQ(passesOfView(both, 2), std::vector<std::string>{});
  }
}

TEST(FramePasses, TheCrowdRunsEveryDrawnGroomsPassesAndWaitsOnce) {
  const Scene s = smallScene("crowd.json");
  GraphChecks checks;
  Renderer r(sharedDevice());
  RenderOptions o;
  o.describePasses = true;
  r.render(s, o);
  const Frame f = r.render(s, o);
  std::vector<std::string> want = {"opaque"};
  std::size_t drawn = 0;
  for (const GroomDrawStats& g : f.stats.grooms)
    if (g.drawn) want.push_back("lod " + std::to_string(g.instance));
  want.push_back("segment budget");
  for (const GroomDrawStats& g : f.stats.grooms)
    if (g.drawn) {
      ++drawn;
      const auto p = groomPasses(g.instance, true);
      want.insert(want.end(), p.begin(), p.end());
    }
  want.push_back("read-back");
  ASSERT_GT(drawn, 50u);
  // the crowd has no shadowed light: no shadow pass in any frame
  EXPECT_EQ(passNames(f.passes), want);
  EXPECT_EQ(f.stats.hostWaits, 1u);
}

TEST(FramesInFlight, SubmittedFramesEqualFramesRenderedOneByOne) {
  const Scene s = loadScene(windScene(scratchDir()));
  Renderer one(sharedDevice());
  one.setFramesInFlight(1);
  std::vector<Frame> want;
  for (int n = 1; n <= 3; ++n) want.push_back(one.render(sceneAtFrame(s, n)));
  Renderer many(sharedDevice());
  many.setFramesInFlight(3);
  std::vector<FrameTicket> tickets;
  for (int n = 1; n <= 3; ++n) {
    Scene still = sceneAtFrame(s, n);
    tickets.push_back(many.submit(still));  // `still` goes away before the frame is done
  }
  for (int i = 2; i >= 0; --i) {  // waited for in any order
    const Frame f = many.wait(tickets[static_cast<std::size_t>(i)]);
    EXPECT_EQ(f.color.rgba, want[static_cast<std::size_t>(i)].color.rgba) << "frame " << i + 1;
    EXPECT_EQ(f.depth, want[static_cast<std::size_t>(i)].depth) << "frame " << i + 1;
    EXPECT_EQ(f.stats.strandsDrawn, want[static_cast<std::size_t>(i)].stats.strandsDrawn);
  }
  EXPECT_NE(errorOf([&] { many.wait(tickets[0]); }).find("already waited"), std::string::npos);
}

TEST(FramesInFlight, PinnedReadBackGivesTheSameFrame) {
  const Scene s = tinyScene();
  RenderOptions o;
  Renderer r(sharedDevice());
  const Frame direct = r.render(s, o);
  sharedDevice().impl()->pinnedReadBack = true;
  const Frame pinned = r.render(s, o);
  const Frame again = r.render(s, o);  // the pinned blocks are reused
  sharedDevice().impl()->pinnedReadBack = false;
  EXPECT_EQ(direct.color.rgba, pinned.color.rgba);
  EXPECT_EQ(direct.depth, pinned.depth);
  EXPECT_EQ(direct.color.rgba, again.color.rgba);
  EXPECT_EQ(again.stats.hostWaits, 1u);
}

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// A scene of the tiny groom blown by wind (each frame differs), written to `dir`.
std::string windScene(const std::string& dir, bool wind) {
  const std::string path = dir + "/wind.json";
  std::ofstream(path) << R"({"resolution": [64, 48],
    "camera": {"position": [0.0, 0.03, 0.2], "target": [0.0, 0.025, 0.0], "fov": 35},
    "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.5], "shadows": true}],
    "shadows": {"resolution": 32},
    "grooms": [{"file": ")"
                      << assetPath("grooms/tiny.hairmesh.json")
                      << (wind ? R"(", "wind": {"strength": 0.01, "frequency": 2}}]})" : R"("}]})");
  return path;
}

TEST(FramesInFlight, CliFilesAreByteIdenticalForOneTwoAndThreeFramesInFlight) {
  const std::string dir = scratchDir();
  const std::string scene = windScene(dir);
  for (int k : {1, 2, 3}) {
    const CommandResult r =
        runCli("render " + quote(scene) + " --frames 1-4 -q --frames-in-flight " +
               std::to_string(k) + " -o " + quote(dir + "/k" + std::to_string(k) + ".####.png"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
  }
  for (const char* n : {"0001", "0002", "0003", "0004"}) {
    const std::string one = readAll(dir + "/k1." + n + ".png");
    ASSERT_FALSE(one.empty()) << n;
    EXPECT_EQ(one, readAll(dir + "/k2." + n + ".png")) << "frame " << n;
    EXPECT_EQ(one, readAll(dir + "/k3." + n + ".png")) << "frame " << n;
  }
  EXPECT_NE(readAll(dir + "/k1.0001.png"), readAll(dir + "/k1.0002.png"));
  // a frame alone is the same file
  const CommandResult alone =
      runCli("render " + quote(scene) + " --frames 3 -q -o " + quote(dir + "/alone.####.png"));
  ASSERT_EQ(alone.exitCode, 0) << alone.output;
  EXPECT_EQ(readAll(dir + "/alone.0003.png"), readAll(dir + "/k2.0003.png"));
  const CommandResult bad =
      runCli("render " + quote(scene) + " --frames-in-flight 9 -o " + quote(dir + "/x.png"));
  EXPECT_EQ(bad.exitCode, 1);
  EXPECT_NE(onlyErrorLine(bad.output).find("--frames-in-flight"), std::string::npos);
}

TEST(FramesInFlight, EveryFrameOfACliRangeAfterTheFirstWaitsOnce) {
  const std::string dir = scratchDir();
  const std::string scene = windScene(dir);
  const CommandResult r = runCli("render " + quote(scene) + " --frames 1-4 --stats -q -o " +
                                 quote(dir + "/w.####.exr"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::vector<int> waits;
  std::istringstream in(r.output);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("host waits: ", 0) == 0) waits.push_back(std::stoi(line.substr(12)));
  ASSERT_EQ(waits.size(), 4u) << r.output;
  for (std::size_t i = 1; i < waits.size(); ++i) EXPECT_EQ(waits[i], 1) << "frame " << i + 1;
}

TEST(FramesInFlight, AFailedWriteStopsTheRangeWithOneLineAndKeepsEarlierFrames) {
  const std::string dir = scratchDir();
  const std::string scene = windScene(dir);
  // frame 3's name is taken by a folder: its image cannot be moved into place
  fs::create_directories(dir + "/out.0003.png");
  const CommandResult r =
      runCli("render " + quote(scene) + " --frames 1-8 -q -o " + quote(dir + "/out.####.png"));
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(onlyErrorLine(r.output).find("out.0003.png"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::is_regular_file(dir + "/out.0001.png"));
  EXPECT_TRUE(fs::is_regular_file(dir + "/out.0002.png"));
  EXPECT_FALSE(fs::exists(dir + "/out.0008.png")) << "the range went on after the failure";
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
}

}  // namespace
}  // namespace clhair::test
