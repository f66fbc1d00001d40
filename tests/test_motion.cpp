// test_motion.cpp — motion vectors of deforming grooms (docs/aovs.md, "How motion is
// computed"), the check that motion explains the next frame (clhair::motionWarpIoU), and
// several views of one assembly (Renderer::renderViews, --views).
//
// A hair mesh whose cage a cage-animation file translates rigidly, and per-frame strand files
// translated from one file to the next, give per pixel the projected translation (the
// previous position of the surface point in the pixel, projected with the camera: within
// 0.05 px on average, with the default filter and, for the cage, Lipp's and none too); a
// frame that is its own previous frame gives 0. A groom in wind (camera still) moves: its
// hair mask of frame t+1 moved by the motion layer matches frame t's with IoU >= 0.8 and
// better than not moving it; a slow turntable (keyed camera, static hair, Lipp's filter)
// >= 0.9. Each view of a two-view render is bit-identical to that camera rendered alone; the
// CLI writes one file per view and frame and refuses unknown view names and --aov with several
// views with one error line. Tiny images and few strands: a few seconds each.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <glm/matrix.hpp>

#include "clhair/animation.h"
#include "clhair/aov.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "io/cyhair.h"
#include "stages/view_math.h"
#include "test_util.h"

namespace clhair::test {
namespace {

using nlohmann::json;

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

// A scene file in `dir` with one groom entry and the camera of the tiny groom's AOV tests
// (looking along -z from 0.2 away); `extra` adds to the scene, `groom` is the groom entry.
std::string writeScene(const std::string& dir, const json& groom, int width, int height,
                       const json& extra = json::object()) {
  json scene = {
      {"resolution", {width, height}},
      {"camera", {{"position", {0.0, 0.03, 0.2}}, {"target", {0.0, 0.025, 0.0}}, {"fov", 35}}},
      {"lights", {{{"type", "directional"}, {"direction", {0.3, 0.8, 0.5}}}}},
      {"grooms", {groom}}};
  scene.update(extra);
  const std::string path = dir + "/scene.json";
  writeFile(path, scene.dump(2));
  return path;
}

// Frame `frame` of `shot` with its AOVs and motion to frame - 1, rendered with `base` (by
// default the default filter: Huang's in these one-view frames).
Frame renderWithMotion(Renderer& r, const Scene& shot, long long frame,
                       const RenderOptions& base = RenderOptions()) {
  const Scene now = sceneAtFrame(shot, static_cast<double>(frame));
  const Scene before = sceneAtFrame(shot, static_cast<double>(frame > 1 ? frame - 1 : frame));
  RenderOptions o = base;
  o.aovs = true;
  o.previous = &before;
  return r.render(now, o);
}

// Mean |motion - expected| over the hair pixels of `f` (frame `frame` of `shot`), where the
// expected motion is that of the world point in the pixel (its centre at depth Z) moved back
// by `worldDelta` and projected with the (still) camera; the count through `hair`.
double meanTranslationError(const Frame& f, const Scene& shot, const glm::vec3& worldDelta,
                            std::size_t& hair, double& meanX) {
  const Scene s = sceneAtFrame(shot, 1.0);
  const gpu::ClhViewGpu v = makeView(s.camera, s.width, s.height);
  const glm::mat4 toView = worldToView(s.camera), toWorld = glm::inverse(toView);
  double error = 0.0;
  hair = 0;
  meanX = 0.0;
  for (std::size_t p = 0; p < f.aovs.z.size(); ++p) {
    if (!(f.aovs.hairAlpha[p] >= 0.5f)) continue;
    const float z = f.aovs.z[p];
    const float px = static_cast<float>(p % s.width) + 0.5f;
    const float py = static_cast<float>(p / s.width) + 0.5f;
    const glm::vec4 pv((px - v.cx) / v.fx * z, -(py - v.cy) / v.fy * z, z, 1.0f);
    const glm::vec3 world = glm::vec3(toWorld * pv) - worldDelta;
    const glm::vec3 q = glm::vec3(toView * glm::vec4(world, 1.0f));
    const float x0 = v.cx + v.fx * q.x / q.z, y0 = v.cy - v.fy * q.y / q.z;
    const double wantX = x0 - px, wantY = py - y0;  // y up
    error += std::abs(f.aovs.motion[2 * p] - wantX) + std::abs(f.aovs.motion[2 * p + 1] - wantY);
    meanX += f.aovs.motion[2 * p];
    ++hair;
  }
  if (hair > 0) meanX /= static_cast<double>(hair);
  return hair > 0 ? error / static_cast<double>(hair) : 1e30;
}

// Lipp's filter (filterMethod 0).
RenderOptions lippsFilter() {
  RenderOptions o;
  o.filterMethod = FilterParams::Method::Lipp;
  return o;
}

}  // namespace

TEST(Motion, CageTranslatedByACageFileGivesTheProjectedTranslation) {
  // Frame 2 of the cage-animation file is frame 1's cage moved by d (every vertex): the
  // strands, generated from the cage, move by d, which the camera sees as about
  // fx * 0.004 / 0.2 = 1.5 px right and 1.1 px up. Without the motion pass (rigid motion
  // only) the motion would be 0 everywhere. With either filter, or none, the motion is that
  // of the fragment whose depth Z reports (with Huang's filter, the default, a pixel's centre
  // word, a linked pixel's that of the strand linked into it; resolving on the conservative
  // layer's nearest word instead measured 0.205 px with Huang's filter, 0.203 without).
  const std::string dir = scratchDir();
  const json groom = {{"file", assetPath("grooms/tiny.hairmesh.json")}, {"strands", 400}};
  const Scene rest = loadScene(writeScene(dir, groom, 64, 48));
  const std::vector<glm::vec3>& cage = rest.grooms.at(0).mesh->positions;
  const glm::vec3 d(0.004f, 0.003f, 0.0f);
  CageAnimation anim;
  anim.frames = 2;
  anim.vertices = static_cast<std::uint32_t>(cage.size());
  anim.positions = cage;
  for (const glm::vec3& q : cage) anim.positions.push_back(q + d);
  saveCageAnimation(anim, dir + "/move.cage");
  json moving = groom;
  moving["cage_animation"] = {{"file", "move.cage"}, {"start_frame", 1}};
  const Scene shot = loadScene(writeScene(dir, moving, 64, 48));
  Renderer r(sharedDevice());
  RenderOptions unfiltered;
  unfiltered.filter = Toggle::Off;
  const RenderOptions configs[] = {RenderOptions(), lippsFilter(), unfiltered};
  const char* names[] = {"default filter", "Lipp's filter", "no filter"};
  for (int c = 0; c < 3; ++c) {
    SCOPED_TRACE(names[c]);
    const Frame f1 = renderWithMotion(r, shot, 1, configs[c]),
                f2 = renderWithMotion(r, shot, 2, configs[c]);
    for (float m : f1.aovs.motion) ASSERT_EQ(m, 0.0f);  // frame 1 is its own previous frame
    std::size_t hair = 0;
    double meanX = 0.0;
    const double error = meanTranslationError(f2, shot, d, hair, meanX);
    ASSERT_GT(hair, 40u);
    EXPECT_LT(error, 0.05);
    EXPECT_LT(meanX, -1.0);  // the hair moved right: its previous position is to the left
    // frame 2 drawn from the moved cage is frame 1 drawn from the rest cage, shifted. Lipp's
    // filter only: with Huang's the half-opaque mask of this sparse 64x48 groom is about 150
    // pixels, a third of them at alpha 0.3-0.7 (alpha fix, anisotropic filter), and its IoU
    // is 0.21-0.23 warped or not, with the motion exact (DESIGN.md, "The default filter")
    if (c == 1) {
      EXPECT_GT(motionWarpIoU(f2.aovs, f1.aovs, 64, 48), maskIoU(f2.aovs, f1.aovs, 64, 48));
    }
  }
}

TEST(Motion, PerFrameStrandFilesGiveTheProjectedTranslation) {
  // Nine straight strands; file 2 holds file 1's points moved by d, strand for strand and
  // point for point, so the pixels of frame 2 moved by d since frame 1.
  const std::string dir = scratchDir();
  const glm::vec3 d(-0.003f, 0.002f, 0.0f);
  for (int frame = 1; frame <= 2; ++frame) {
    CyHair h;
    for (int s = 0; s < 9; ++s) {
      h.segments.push_back(8);
      for (int k = 0; k < 9; ++k) {
        glm::vec3 q(-0.02f + 0.005f * s, 0.005f + 0.005f * k, 0.0f);
        if (frame == 2) q += d;
        h.points.insert(h.points.end(), {q.x, q.y, q.z});
      }
    }
    writeCyHair(h, dir + "/v.000" + std::to_string(frame) + ".hair");
  }
  const json groom = {{"strands_file", "v.####.hair"}, {"appearance", {{"strand_width", 0.002}}}};
  const Scene shot = loadScene(writeScene(dir, groom, 64, 48));
  Renderer r(sharedDevice());
  const Frame f2 = renderWithMotion(r, shot, 2);
  std::size_t hair = 0;
  double meanX = 0.0;
  const double error = meanTranslationError(f2, shot, d, hair, meanX);
  ASSERT_GT(hair, 40u);
  EXPECT_LT(error, 0.05);
  EXPECT_GT(meanX, 1.0);  // moved left: the previous position is to the right
}

// The same with follow hairs grown from the moving strands (children of the previous frame's
// guides, host/groom/children.h): every child moved by d too.
TEST(Motion, ChildrenOfPerFrameStrandFilesGiveTheProjectedTranslation) {
  const std::string dir = scratchDir();
  const glm::vec3 d(-0.003f, 0.002f, 0.0f);
  for (int frame = 1; frame <= 2; ++frame) {
    CyHair h;
    for (int s = 0; s < 9; ++s) {
      h.segments.push_back(8);
      for (int k = 0; k < 9; ++k) {
        glm::vec3 q(-0.02f + 0.005f * s, 0.005f + 0.005f * k, 0.0f);
        if (frame == 2) q += d;
        h.points.insert(h.points.end(), {q.x, q.y, q.z});
      }
    }
    writeCyHair(h, dir + "/v.000" + std::to_string(frame) + ".hair");
  }
  const json groom = {{"strands_file", "v.####.hair"},
                      {"appearance", {{"strand_width", 0.002}}},
                      {"children", {{"count", 6}, {"radius", 0.004}, {"tip_spread", 1}}}};
  const Scene shot = loadScene(writeScene(dir, groom, 64, 48));
  ASSERT_EQ(shot.grooms[0].strands->children.count, 6u);
  Renderer r(sharedDevice());
  const Frame f2 = renderWithMotion(r, shot, 2);
  std::size_t hair = 0;
  double meanX = 0.0;
  const double error = meanTranslationError(f2, shot, d, hair, meanX);
  // most hair pixels are children's (six per guide)
  std::size_t guideHair = 0;
  {
    json bare = groom;
    bare["children"] = {{"count", 0}};
    const Scene guidesOnly = loadScene(writeScene(dir, bare, 64, 48));
    double unused = 0.0;
    meanTranslationError(renderWithMotion(r, guidesOnly, 2), guidesOnly, d, guideHair, unused);
  }
  ASSERT_GT(hair, guideHair + guideHair / 2);
  EXPECT_LT(error, 0.05);
  EXPECT_GT(meanX, 1.0);
}

TEST(Motion, WindMotionMovesTheNextFrameOntoThePrevious) {
  // The tiny groom in a strong wind (tips sway about 3.7 px a frame here), camera still:
  // frame t's hair warped to frame t+1 by t+1's motion matches t+1's hair with IoU >= 0.8
  // (the target for the wind shot), clearly better than not warping it (about 0.77:
  // what rigid-only motion, 0 here, gives).
  const std::string dir = scratchDir();
  const json groom = {
      {"file", assetPath("grooms/tiny.hairmesh.json")},
      {"strands", 3000},
      {"wind",
       {{"strength", 0.04}, {"direction", {1, 0, 0}}, {"frequency", 3.0}, {"wavelength", 0.5}}}};
  const Scene shot = loadScene(writeScene(dir, groom, 96, 72));
  Renderer r(sharedDevice());
  const Frame a = renderWithMotion(r, shot, 4), b = renderWithMotion(r, shot, 5);
  double moving = 0.0;
  for (std::size_t p = 0; p < b.aovs.z.size(); ++p)
    if (b.aovs.hairAlpha[p] >= 0.5f)
      moving = std::max<double>(moving, std::abs(b.aovs.motion[2 * p]));
  const double warped = motionWarpIoU(b.aovs, a.aovs, 96, 72);
  const double still = maskIoU(b.aovs, a.aovs, 96, 72);
  EXPECT_GT(moving, 1.0);
  EXPECT_GE(warped, 0.8) << "unwarped " << still;
  EXPECT_GT(warped, still + 0.05);
}

TEST(Motion, SlowTurntableMotionMovesTheNextFrameOntoThePrevious) {
  // A camera orbiting the still groom by 3 degrees a frame (about 0.8 px at the hair):
  // IoU >= 0.9 after warping, and better than without (about 0.93; motion pointing the
  // wrong way gives about 0.91). Lipp's filter: the motion here is the camera's reprojection
  // of Z (no motion pass), but one sample per pixel without Lipp's coverage from the
  // conservative layer gives a mask that a sub-pixel move changes more than any warp
  // explains: 0.857 warped against 0.874 with Huang's filter, 0.844 against 0.852 with
  // all of its parts off (DESIGN.md, "The default filter").
  const std::string dir = scratchDir();
  // every strand in every frame: LOD's strand count follows the orbit's widths, and the
  // strands it swaps between frames are not motion
  const json groom = {{"file", assetPath("grooms/tiny.hairmesh.json")},
                      {"strands", 3000},
                      {"lod", {{"enabled", false}}}};
  const double radius = 0.2, step = 3.0 * 3.14159265358979 / 180.0;
  json keys = json::array();
  for (int k = 1; k <= 3; ++k) {
    const double a = step * (k - 1);
    keys.push_back({{"frame", k},
                    {"position", {radius * std::sin(a), 0.03, radius * std::cos(a)}},
                    {"target", {0.0, 0.025, 0.0}}});
  }
  const json extra = {{"camera",
                       {{"position", {0.0, 0.03, radius}},
                        {"target", {0.0, 0.025, 0.0}},
                        {"fov", 35},
                        {"keys", keys}}}};
  const Scene shot = loadScene(writeScene(dir, groom, 96, 72, extra));
  Renderer r(sharedDevice());
  const Frame a = renderWithMotion(r, shot, 2, lippsFilter()),
              b = renderWithMotion(r, shot, 3, lippsFilter());
  const double warped = motionWarpIoU(b.aovs, a.aovs, 96, 72);
  const double still = maskIoU(b.aovs, a.aovs, 96, 72);
  EXPECT_GE(warped, 0.9) << "unwarped " << still;
  EXPECT_GT(warped, still + 0.01);
}

namespace {

// One assembly drawn into two views (a camera and one moved 4 cm right and turned) against
// each camera rendered alone at `msaa` samples: bit-identical, since each view's raster,
// shading, filter and composite see the same strands, words and depths (LOD off, both views
// see the whole groom, so neither culls or thins what the other draws). The default filter
// ("auto") is Lipp's in several views and Huang's in one (DESIGN.md, "The default
// filter"), so at MSAA 1 each view equals its camera alone with Lipp's filter, and differs
// from its camera alone with the default, which links. At MSAA 4 no filter runs in either.
// 79x59 pixels: no view's depth or G-buffer slice is a multiple of the sub-buffer alignment
// (128 bytes on PoCL), so the second view's slices start after padding.
void expectEachViewIsItsSingleRender(int msaa) {
  const std::string dir = scratchDir();
  const json groom = {{"file", assetPath("grooms/tiny.hairmesh.json")},
                      {"strands", 800},
                      {"lod", {{"enabled", false}}}};  // the files draw with LOD by default
  const json extra = {{"cameras",
                       {{{"name", "left"}, {"offset", {-0.01, 0.0, 0.0}}},
                        {{"name", "side"},
                         {"position", {0.12, 0.04, 0.16}},
                         {"target", {0.0, 0.025, 0.0}},
                         {"fov", 40}}}},
                      {"spheres", {{{"center", {0.0, 0.0, -0.02}}, {"radius", 0.02}}}}};
  const Scene scene = loadScene(writeScene(dir, groom, 79, 59, extra));
  ASSERT_EQ(scene.views.size(), 2u);
  std::vector<Camera> cams;
  for (const View& v : scene.views) cams.push_back(viewCamera(scene, v));
  EXPECT_NEAR(cams[0].position.x, -0.01f, 1e-6f);  // the offset is along the camera's right
  Renderer r(sharedDevice());
  RenderOptions o;
  o.lod = Toggle::Off;
  o.msaa = msaa;
  // the maps at the scene's resolution, as a frame of several views builds them (a single
  // view's follow its camera: RenderOptions::shadowResFromCamera)
  o.shadowResFromCamera = false;
  const std::vector<Frame> both = r.renderViews(scene, cams, o);
  ASSERT_EQ(both.size(), 2u);
  for (std::size_t v = 0; v < 2; ++v) {
    Scene one = scene;
    one.camera = cams[v];
    RenderOptions lipp = o;
    lipp.filterMethod = FilterParams::Method::Lipp;
    const Frame alone = r.render(one, msaa == 1 ? lipp : o);  // MSAA 4: no filter at all
    if (msaa > 1) {
      EXPECT_EQ(alone.stats.linkSelecting, 0u) << "view " << v;
    }
    std::size_t hair = 0, differ = 0;
    for (std::size_t i = 0; i < alone.color.rgba.size(); ++i)
      differ += alone.color.rgba[i] != both[v].color.rgba[i];
    if (msaa == 1) {  // one view alone: Huang's filter by default, which links empty pixels
      const Frame byDefault = r.render(one, o);
      EXPECT_GT(byDefault.stats.linkSelecting, 0u) << "view " << v;
      EXPECT_EQ(both[v].stats.linkSelecting, 0u) << "view " << v;
      EXPECT_NE(byDefault.color.rgba, both[v].color.rgba) << "view " << v;
    }
    for (std::size_t p = 0; p < alone.depth.size(); ++p)
      hair += alone.depth[p] < 1.0f && alone.depth[p] != both[1 - v].depth[p];
    EXPECT_EQ(differ, 0u) << "view " << v;
    EXPECT_EQ(both[v].stats.strandsDrawn, alone.stats.strandsDrawn) << "view " << v;
    EXPECT_GT(hair, 100u) << "view " << v << ": the two views must differ";
  }
}

}  // namespace

TEST(Views, EachViewOfATwoViewRenderIsTheSingleViewRenderOfItsCamera) {
  expectEachViewIsItsSingleRender(1);
}

// MSAA 4: five layers per view in the two-view kernel's G-buffers (the views' slices side by
// side), each slice shaded in place as its view's G-buffer.
TEST(Views, EachViewIsTheSingleViewRenderAtMsaa4) { expectEachViewIsItsSingleRender(4); }

TEST(Views, CliWritesOneFilePerViewAndRefusesUnknownNames) {
  const std::string dir = scratchDir();
  const json groom = {{"file", assetPath("grooms/tiny.hairmesh.json")}, {"strands", 200}};
  const json extra = {{"cameras",
                       {{{"name", "left"}, {"offset", {-0.003, 0.0, 0.0}}},
                        {{"name", "right"}, {"offset", {0.003, 0.0, 0.0}}}}}};
  const std::string scene = writeScene(dir, groom, 48, 36, extra);
  CommandResult c =
      runCli("render " + quote(scene) + " -q --frames 1-2 -o " + quote(dir + "/s.#.%v.png"));
  ASSERT_EQ(c.exitCode, 0) << c.output;
  for (const char* f : {"s.1.left.png", "s.1.right.png", "s.2.left.png", "s.2.right.png"})
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + f)) << f;
  c = runCli("render " + quote(scene) + " -q --views right -o " + quote(dir + "/one.png"));
  ASSERT_EQ(c.exitCode, 0) << c.output;
  EXPECT_TRUE(std::filesystem::exists(dir + "/one.png"));
  c = runCli("render " + quote(scene) + " -q --views left,top -o " + quote(dir + "/bad.png"));
  EXPECT_EQ(c.exitCode, 1);
  EXPECT_NE(onlyErrorLine(c.output).find("no view named \"top\""), std::string::npos) << c.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/bad.left.png"));
  c = runCli("render " + quote(scene) + " -q --aov all -o " + quote(dir + "/x.exr"));
  EXPECT_EQ(c.exitCode, 1);
  EXPECT_NE(onlyErrorLine(c.output).find("--aov writes one view"), std::string::npos) << c.output;
  // Huang's filter runs on one view at a time: refused, nothing written (it was silently
  // replaced by Lipp's filter once)
  c = runCli("render " + quote(scene) + " -q --filter huang -o " + quote(dir + "/h.png"));
  EXPECT_EQ(c.exitCode, 1);
  EXPECT_NE(onlyErrorLine(c.output).find("Huang's filter takes one view"), std::string::npos)
      << c.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/h.left.png"));
  // a malformed "cameras" entry: one line naming the file and the entry
  const json twice = {{"cameras", {{{"name", "a"}, {"offset", {0, 0, 0}}}, {{"name", "a"}}}}};
  c = runCli("render " + quote(writeScene(dir, groom, 48, 36, twice)) + " -q -o " +
             quote(dir + "/t.png"));
  EXPECT_EQ(c.exitCode, 1);
  EXPECT_NE(onlyErrorLine(c.output).find("cameras[1].name"), std::string::npos) << c.output;
}

}  // namespace clhair::test
