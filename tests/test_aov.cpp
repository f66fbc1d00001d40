// test_aov.cpp — layers for compositing (--aov, clhair/aov.h, docs/aovs.md).
//
// The --aov list parser; the CLI's multi-channel EXR read back with OpenImageIO (channel
// names and per-channel types as documented, the beauty identical to a plain render, one
// error line and no file for a bad name or a non-EXR output); Z against the G-buffer depth
// the hair was composited with and against the analytic depth of a sphere; the tangent of
// straight vertical strands against (0, 1, 0) within the octahedral code's step; motion of a
// groom translated by a transform key against the projected translation (and against the
// shift of the hair's coverage centroid between the two frames), zero in a range's frame 1;
// motion of static hair and a sphere under a keyed camera move against the projected shift;
// with two grooms, motion follows the groom that set the pixel's depth and hair.A combines
// the grooms' coverages like "over".
// Tiny images and few strands: seconds each.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include "clhair/aov.h"
#include "clhair/error.h"
#include "clhair/gpu_types.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "exr_file.h"
#include "io/cyhair.h"
#include "stages/view_math.h"
#include "test_util.h"

namespace clhair::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr std::uint64_t kEmptyWord = ~std::uint64_t(0);  // CLH_GBUF_EMPTY

// An EXR read back channel by channel, as float, with each channel's stored type.

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

// A 64x48 scene of the tiny groom seen along -z (the camera's right is world +x); `groom`
// adds to its groom entry.
std::string tinyAovScene(const std::string& dir, const json& groom = json::object()) {
  json g = {{"file", assetPath("grooms/tiny.hairmesh.json")}};
  g.update(groom);
  const json scene = {
      {"resolution", {64, 48}},
      {"camera", {{"position", {0.0, 0.03, 0.2}}, {"target", {0.0, 0.025, 0.0}}, {"fov", 35}}},
      {"lights", {{{"type", "directional"}, {"direction", {0.3, 0.8, 0.5}}}}},
      {"grooms", {g}}};
  const std::string path = dir + "/scene.json";
  writeFile(path, scene.dump(2));
  return path;
}

// Nine straight vertical strands (root at the bottom) 0.01 apart in x, in the plane z = 0, in
// front of a sphere; the camera at z = 0.3 looks along -z.
Scene strandsBeforeSphere() {
  StrandGroom g;
  g.name = "vertical";
  g.appearance.strandWidth = 0.004f;
  for (int s = 0; s < 9; ++s) {
    g.pointCounts.push_back(9);
    for (int k = 0; k < 9; ++k)
      g.points.emplace_back(-0.04f + 0.01f * s, -0.05f + 0.0125f * k, 0.0f);
  }
  Scene sc;
  sc.width = 64;
  sc.height = 48;
  sc.camera.position = glm::vec3(0.0f, 0.0f, 0.3f);
  sc.camera.target = glm::vec3(0.0f);
  sc.camera.fovYDegrees = 35.0f;
  Light l;
  l.direction = glm::normalize(glm::vec3(0.3f, 1.0f, 0.6f));
  sc.lights.push_back(l);
  sc.spheres.push_back({glm::vec3(0.0f, 0.0f, -0.1f), 0.05f, glm::vec3(0.5f)});
  sc.grooms.push_back(GroomInstance("vertical", std::make_shared<const StrandGroom>(std::move(g))));
  return sc;
}

// The vertical strands of strandsBeforeSphere as a strand file with its sphere, in a
// scene; `transform` and `cameraKeys` animate them. Renders frames 1 and 2 with every
// layer to dir/f.1.exr and dir/f.2.exr.
void renderTwoFrames(const std::string& dir, const json& transform, const json& cameraKeys) {
  CyHair h;
  const Scene still = strandsBeforeSphere();
  for (std::uint32_t n : still.grooms[0].strands->pointCounts) h.segments.push_back(n - 1);
  for (const glm::vec3& q : still.grooms[0].strands->points)
    h.points.insert(h.points.end(), {q.x, q.y, q.z});
  writeCyHair(h, dir + "/vertical.hair");
  json groom = {{"strands_file", "vertical.hair"}, {"appearance", {{"strand_width", 0.004}}}};
  if (!transform.empty()) groom["transform"] = transform;
  json camera = {{"position", {0.0, 0.0, 0.3}}, {"target", {0.0, 0.0, 0.0}}, {"fov", 35}};
  if (!cameraKeys.empty()) camera["keys"] = cameraKeys;
  const json scene = {{"resolution", {64, 48}},
                      {"camera", camera},
                      {"lights", {{{"type", "directional"}, {"direction", {0.3, 1.0, 0.6}}}}},
                      {"spheres", {{{"center", {0.0, 0.0, -0.1}}, {"radius", 0.05}}}},
                      {"grooms", {groom}}};
  writeFile(dir + "/scene.json", scene.dump(2));
  const CommandResult r = runCli("render " + quote(dir + "/scene.json") +
                                 " -q --frames 1-2 --aov all -o " + quote(dir + "/f.#.exr"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
}

// The focal length in pixels of these 64x48 scenes (35 degrees vertical field of view).
const double kFx = 0.5 * 48.0 / std::tan(35.0 * 3.14159265358979 / 360.0);

}  // namespace

TEST(Aov, ListParsesInTheDocumentedOrderAndRefusesUnknownNames) {
  EXPECT_EQ(parseAovList("all"), (std::vector<Aov>{Aov::Rgba, Aov::Z, Aov::Alpha, Aov::Tangent,
                                                   Aov::Motion, Aov::Strand}));
  EXPECT_EQ(parseAovList("motion,z,motion"), (std::vector<Aov>{Aov::Z, Aov::Motion}));
  for (const char* bad : {"z,depth", "", "z,,rgba", "Z"}) {
    SCOPED_TRACE(bad);
    try {
      parseAovList(bad);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
      EXPECT_NE(msg.find("rgba, z, alpha, tangent, motion, strand, cryptomatte or all"),
                std::string::npos)
          << msg;
    }
  }
}

TEST(Aov, CliWritesTheDocumentedChannelsAndTheSameBeauty) {
  const std::string dir = scratchDir();
  const std::string scene = tinyAovScene(dir);
  const CommandResult a =
      runCli("render " + quote(scene) + " -q --aov all -o " + quote(dir + "/layers.exr"));
  ASSERT_EQ(a.exitCode, 0) << a.output;
  const CommandResult b = runCli("render " + quote(scene) + " -q -o " + quote(dir + "/plain.exr"));
  ASSERT_EQ(b.exitCode, 0) << b.output;
  const ExrFile f = readExr(dir + "/layers.exr");
  ASSERT_EQ(f.width, 64);
  ASSERT_EQ(f.height, 48);
  const std::map<std::string, OIIO::TypeDesc> want = {
      {"R", OIIO::TypeDesc::HALF},          {"G", OIIO::TypeDesc::HALF},
      {"B", OIIO::TypeDesc::HALF},          {"A", OIIO::TypeDesc::HALF},
      {"Z", OIIO::TypeDesc::FLOAT},         {"hair.A", OIIO::TypeDesc::HALF},
      {"tangent.X", OIIO::TypeDesc::HALF},  {"tangent.Y", OIIO::TypeDesc::HALF},
      {"tangent.Z", OIIO::TypeDesc::HALF},  {"motion.X", OIIO::TypeDesc::FLOAT},
      {"motion.Y", OIIO::TypeDesc::FLOAT},  {"strand.groom", OIIO::TypeDesc::FLOAT},
      {"strand.id", OIIO::TypeDesc::FLOAT}, {"strand.u", OIIO::TypeDesc::FLOAT}};
  EXPECT_EQ(f.channels.size(), want.size());
  for (const auto& [name, type] : want) {
    SCOPED_TRACE(name);
    ASSERT_EQ(f.types.count(name), 1u);
    EXPECT_EQ(f.types.at(name), type);
  }
  // the beauty is the plain render's, value for value
  const ExrFile plain = readExr(dir + "/plain.exr");
  for (const char* c : {"R", "G", "B", "A"}) EXPECT_EQ(f.channels.at(c), plain.channels.at(c)) << c;
  // the layers are filled: hair covers some pixels, carries unit tangents, lies in front.
  // Huang's filter (the default) gives the tiny groom's sub-pixel strands their coverage,
  // alpha = M / (M + N) per strand, so most of its pixels are less than half opaque: the
  // pixels are counted by any hair alpha, the depth checked where it is at least half
  std::size_t hair = 0, background = 0;
  for (std::size_t p = 0; p < 64 * 48; ++p) {
    if (f.channels.at("Z")[p] == kAovBackgroundZ) ++background;
    if (f.channels.at("hair.A")[p] <= 0.0f) continue;
    ++hair;
    if (f.channels.at("hair.A")[p] >= 0.5f) {
      EXPECT_LT(f.channels.at("Z")[p], 1.0f);  // hair at least half opaque is in the depth
    }
  }
  EXPECT_GT(hair, 20u);
  EXPECT_GT(background, 20u);
  std::size_t tangents = 0;
  for (std::size_t p = 0; p < 64 * 48; ++p) {
    const float x = f.channels.at("tangent.X")[p], y = f.channels.at("tangent.Y")[p],
                z = f.channels.at("tangent.Z")[p];
    if (x == 0.0f && y == 0.0f && z == 0.0f) continue;
    ++tangents;
    EXPECT_NEAR(std::sqrt(x * x + y * y + z * z), 1.0f, 2e-3f);
  }
  EXPECT_GT(tangents, 10u);
}

TEST(Aov, CliRefusesBadNamesAndNonExrOutputWithOneLine) {
  const std::string dir = scratchDir();
  const std::string scene = tinyAovScene(dir);
  struct Case {
    std::string args, mention;
  } cases[] = {{"--aov rgba,depth -o " + quote(dir + "/a.exr"), "unknown layer \"depth\""},
               {"--aov z -o " + quote(dir + "/a.png"), "is not .exr"},
               {"--aov , -o " + quote(dir + "/a.exr"), "an empty name"}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const CommandResult r = runCli("render " + quote(scene) + " " + c.args);
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(onlyErrorLine(r.output).find(c.mention), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(dir + "/a.exr"));
  EXPECT_FALSE(fs::exists(dir + "/a.png"));
}

TEST(Aov, DepthIsTheHairsGBufferDepthAndTheSpheresAnalyticDepth) {
  Renderer r(sharedDevice());
  const Scene s = strandsBeforeSphere();
  RenderOptions o;
  o.aovs = true;
  o.captureGBuffer = true;
  o.filter = Toggle::Off;  // the composite takes the hair's depth from the centre layer alone
  const Frame f = r.render(s, o);
  const std::size_t pixels = 64 * 48;
  ASSERT_EQ(f.aovs.z.size(), pixels);
  gpu::ClhGroomGpu g;
  ASSERT_EQ(f.rasterGroom.size(), sizeof(g));
  std::memcpy(&g, f.rasterGroom.data(), sizeof(g));
  const gpu::ClhViewGpu v = makeView(s.camera, s.width, s.height);
  const glm::mat4 toWorld = glm::inverse(worldToView(s.camera));
  std::size_t hair = 0, sphere = 0, background = 0;
  for (std::size_t p = 0; p < pixels; ++p) {
    const float z = f.aovs.z[p];
    const std::uint64_t word = f.gbuffer[p];
    if (f.aovs.hairAlpha[p] >= 0.5f && word != kEmptyWord) {
      // hair at least half opaque: its centre word's depth (composite.cl)
      ++hair;
      EXPECT_EQ(z, gpu::clh_depth_decode(gpu::clh_gbuf_depth(word), g.depth_near, g.depth_far));
      EXPECT_NEAR(z, 0.3f, 1e-3f);  // the strands' plane
      continue;
    }
    if (f.aovs.hairAlpha[p] > 0.0f) continue;
    // no hair: the ray through the pixel centre against the sphere; view depth = t for a
    // view-space direction of unit z
    const float px = static_cast<float>(p % 64) + 0.5f, py = static_cast<float>(p / 64) + 0.5f;
    const glm::vec3 d =
        glm::vec3(toWorld * glm::vec4((px - v.cx) / v.fx, -(py - v.cy) / v.fy, 1.0f, 0.0f));
    const glm::vec3 oc = s.camera.position - s.spheres[0].center;
    const float a = glm::dot(d, d), b = glm::dot(oc, d),
                c = glm::dot(oc, oc) - s.spheres[0].radius * s.spheres[0].radius;
    const float disc = b * b - a * c;
    if (disc < 0.0f) {
      ++background;
      EXPECT_EQ(z, kAovBackgroundZ) << "pixel " << p;
      continue;
    }
    if (disc < 1e-3f * a * c + 1e-9f) continue;  // the silhouette: either answer is fair
    ++sphere;
    EXPECT_NEAR(z, (-b - std::sqrt(disc)) / a, 1e-4f) << "pixel " << p;
  }
  EXPECT_GT(hair, 50u);
  EXPECT_GT(sphere, 50u);
  EXPECT_GT(background, 50u);
}

TEST(Aov, TangentOfStraightVerticalStrandsIsPlusY) {
  Renderer r(sharedDevice());
  RenderOptions o;
  o.aovs = true;
  const Frame f = r.render(strandsBeforeSphere(), o);
  // the octahedral code has 8 bits per axis: one step is 2/255 before normalising
  const float step = 2.0f / 255.0f;
  std::size_t hair = 0;
  for (std::size_t p = 0; p < 64 * 48; ++p) {
    const float* t = &f.aovs.tangent[p * 3];
    if (t[0] == 0.0f && t[1] == 0.0f && t[2] == 0.0f) continue;
    ++hair;
    EXPECT_NEAR(t[0], 0.0f, step) << "pixel " << p;
    EXPECT_NEAR(t[1], 1.0f, step * step) << "pixel " << p;
    EXPECT_NEAR(t[2], 0.0f, step) << "pixel " << p;
  }
  EXPECT_GT(hair, 50u);
}

TEST(Aov, RigidTranslationGivesTheProjectedTranslationInPixels) {
  const std::string dir = scratchDir();
  // The vertical strands of strandsBeforeSphere as a strand file, moved +0.013 in world x
  // from frame 1 to 2 by a transform key. The camera's right is world x and every strand
  // stays at view depth 0.3, so the hair moves fx * 0.013 / 0.3 (about 3.3) pixels right:
  // its motion to the previous frame is the opposite. The sphere behind does not move.
  const double dx = 0.013, depth = 0.3;
  renderTwoFrames(dir, {{"keys", {{{"frame", 1}}, {{"frame", 2}, {"translate", {dx, 0.0, 0.0}}}}}},
                  {});
  const ExrFile f1 = readExr(dir + "/f.1.exr"), f2 = readExr(dir + "/f.2.exr");
  ASSERT_EQ(f2.width, 64);
  const double want = -kFx * dx / depth;
  double error = 0.0, meanMotion = 0.0;
  std::size_t hair = 0, opaque = 0;
  for (std::size_t p = 0; p < 64 * 48; ++p) {
    EXPECT_EQ(f1.channels.at("motion.X")[p], 0.0f);  // frame 1 is its own previous frame
    EXPECT_EQ(f1.channels.at("motion.Y")[p], 0.0f);
    const float mx = f2.channels.at("motion.X")[p], my = f2.channels.at("motion.Y")[p];
    if (f2.channels.at("hair.A")[p] >= 0.5f) {  // hair in the depth: the hair's motion
      ASSERT_NEAR(f2.channels.at("Z")[p], depth, 1e-3);
      error += std::abs(mx - want) + std::abs(my);
      meanMotion += mx;
      ++hair;
    } else if (f2.channels.at("hair.A")[p] == 0.0f) {
      if (f2.channels.at("Z")[p] < 1.0f) ++opaque;
      EXPECT_EQ(mx, 0.0f) << "pixel " << p;  // the sphere and the background stay
      EXPECT_EQ(my, 0.0f) << "pixel " << p;
    }
  }
  ASSERT_GT(hair, 50u);
  EXPECT_GT(opaque, 50u);
  EXPECT_LT(error / static_cast<double>(hair), 0.05) << "want " << want;
  meanMotion /= static_cast<double>(hair);
  // independent of Z and of the projection: the hair's coverage centroid moved by minus
  // the motion (coverage changes a little with the sub-pixel phase of each strand)
  auto centroidX = [](const ExrFile& f) {
    double sum = 0.0, weight = 0.0;
    for (std::size_t p = 0; p < 64 * 48; ++p) {
      sum += f.channels.at("hair.A")[p] * (static_cast<double>(p % 64) + 0.5);
      weight += f.channels.at("hair.A")[p];
    }
    return sum / weight;
  };
  EXPECT_NEAR(centroidX(f1) - centroidX(f2), meanMotion, 0.25);
}

TEST(Aov, CameraKeysMoveEveryStaticSurfaceByTheProjectedShift) {
  const std::string dir = scratchDir();
  // The camera (and its target) moves +0.004 in world x from frame 1 to 2; nothing else
  // moves. A static point at view depth z appears fx * 0.004 / z pixels further left, so
  // its motion to the previous frame is +fx * 0.004 / z: the hair's plane and the sphere's
  // varying depth alike, and the background stays at 0.
  const double dx = 0.004;
  renderTwoFrames(
      dir, {},
      {{{"frame", 1}}, {{"frame", 2}, {"position", {dx, 0.0, 0.3}}, {"target", {dx, 0.0, 0.0}}}});
  const ExrFile f = readExr(dir + "/f.2.exr");
  ASSERT_EQ(f.width, 64);
  double hairError = 0.0, sphereError = 0.0;
  std::size_t hair = 0, sphere = 0;
  for (std::size_t p = 0; p < 64 * 48; ++p) {
    const float z = f.channels.at("Z")[p];
    const float mx = f.channels.at("motion.X")[p], my = f.channels.at("motion.Y")[p];
    if (z == kAovBackgroundZ) {
      EXPECT_EQ(mx, 0.0f);
      EXPECT_EQ(my, 0.0f);
      continue;
    }
    const double err = std::abs(mx - kFx * dx / z) + std::abs(my);
    if (f.channels.at("hair.A")[p] >= 0.5f) {
      hairError += err;
      ++hair;
    } else if (f.channels.at("hair.A")[p] == 0.0f) {
      sphereError += err;
      ++sphere;
    }
  }
  ASSERT_GT(hair, 50u);
  ASSERT_GT(sphere, 50u);
  EXPECT_LT(hairError / static_cast<double>(hair), 0.05);
  EXPECT_LT(sphereError / static_cast<double>(sphere), 0.05);
}

TEST(Aov, MotionFollowsTheGroomThatOwnsThePixelsDepth) {
  // Two instances of the vertical strands through the library API: groom 0 static in the
  // plane z = 0 (view depth 0.3), groom 1 offset by half the strand spacing and 0.05 nearer
  // (view depth 0.25), translated +0.006 in x since the previous frame. Pixels whose depth
  // groom 1 set move by -fx * 0.006 / 0.25; groom 0's and the sphere's do not move at all.
  // hair.A is groom 1's coverage over groom 0's, as each alone has them.
  Scene now = strandsBeforeSphere();
  now.grooms.push_back(now.grooms[0]);
  now.grooms[1].name = "nearer";
  const glm::vec3 offset(0.005f, 0.0f, 0.05f), dx(0.006f, 0.0f, 0.0f);
  Scene before = now;
  before.grooms[1].transform = glm::translate(glm::mat4(1.0f), offset);
  now.grooms[1].transform = glm::translate(glm::mat4(1.0f), offset + dx);
  Renderer r(sharedDevice());
  RenderOptions o;
  o.aovs = true;
  o.previous = &before;
  const Frame f = r.render(now, o);
  // each groom alone (no shadowed light: neither changes the other's shading or coverage)
  Scene only0 = now, only1 = now;
  only0.grooms.pop_back();
  only1.grooms.erase(only1.grooms.begin());
  o.previous = nullptr;
  const std::vector<float> a0 = r.render(only0, o).aovs.hairAlpha;
  const std::vector<float> a1 = r.render(only1, o).aovs.hairAlpha;
  const double want = -kFx * dx.x / 0.25;
  double error = 0.0;
  std::size_t near = 0, far = 0;
  for (std::size_t p = 0; p < 64 * 48; ++p) {
    const float z = f.aovs.z[p], mx = f.aovs.motion[p * 2], my = f.aovs.motion[p * 2 + 1];
    if (std::abs(z - 0.25f) < 1e-3f) {
      error += std::abs(mx - want) + std::abs(my);
      ++near;
    } else if (z != kAovBackgroundZ) {
      if (std::abs(z - 0.3f) < 1e-3f) ++far;
      EXPECT_EQ(mx, 0.0f) << "pixel " << p << " at depth " << z;
      EXPECT_EQ(my, 0.0f) << "pixel " << p << " at depth " << z;
    }
    // coverage combines like "over", groom 1 over groom 0
    EXPECT_NEAR(f.aovs.hairAlpha[p], a1[p] + (1.0f - a1[p]) * a0[p], 1e-6f) << "pixel " << p;
  }
  ASSERT_GT(near, 30u);
  std::size_t both = 0;  // the check above saw overlapping coverage
  for (std::size_t p = 0; p < 64 * 48; ++p) both += a0[p] > 0.1f && a1[p] > 0.1f;
  EXPECT_GT(both, 10u);
  EXPECT_GT(far, 30u);
  EXPECT_LT(error / static_cast<double>(near), 0.05) << "want " << want;
}

}  // namespace clhair::test
