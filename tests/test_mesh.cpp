// test_mesh.cpp — opaque triangle meshes (include/clhair/triangle_mesh.h, kernels/mesh.cl):
// they hide hair exactly as the analytic primitives do, they cast into the hair's deep
// opacity maps, and malformed OBJ files are refused with one error line.
//
// Occlusion: a plane made of two triangles (much larger than the view) against the same
// plane given analytically, cutting through a dense groom. Both write the exact view depth
// of the plane along each pixel's center ray (opaque.cl in world space, mesh.cl in view
// space), so they differ by float rounding only (~1e-7 relative): a hair sample can flip
// only where it lies within that distance of the plane, i.e. along the line where the
// plane cuts the hair. Tolerance: at least 99.5 % of the pixels where either frame has hair
// hold the same hair G-buffer word, and the depth agrees within 1e-5 relative on at least
// 99.5 % of all pixels.
// Shadows: a horizontal occluder above the groom, the only light above it, shadowed.
// Without the occluder the hair is lit; with the mesh occluder the light's opaque depth map
// is the occluder everywhere over the groom, so the hair keeps only the ambient term
// (bound: what the light adds to the hair's summed colour, against the same frame without
// the light, falls below 5 % of what it adds unoccluded; exactly 0 in theory); against the analytic
// plane occluder the per-pixel colour agrees within 1e-4 (linear) on at least 99.5 % of the hair
// pixels (the same argument: both depth maps hold the same plane up to rounding).
// Malformed files: the CLI is run on scenes naming truncated, NaN, out-of-range, huge
// (sparse, so no disk is used), missing and PLY files: exit 1, one "clhair: error:" line
// naming the scene and the mesh as the scene wrote it, no output file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "clhair/triangle_mesh.h"
#include "groom/presets.h"
#include "test_util.h"

namespace clhair {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

// A square of side 2 * half in the plane dot(normal, x) = dot(normal, center), as two
// triangles (one of them wound the other way round, so both windings are drawn).
std::shared_ptr<const TriangleMesh> squareMesh(const glm::vec3& center, const glm::vec3& normal,
                                               float half) {
  const glm::vec3 n = glm::normalize(normal);
  const glm::vec3 helper = std::fabs(n.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  const glm::vec3 u = glm::normalize(glm::cross(helper, n)) * half,
                  v = glm::cross(n, glm::normalize(u)) * half;
  TriangleMesh m;
  m.name = "square";
  m.positions = {center - u - v, center + u - v, center + u + v, center - u + v};
  m.indices = {0, 1, 2, 0, 3, 2};
  return std::make_shared<const TriangleMesh>(std::move(m));
}

// A dense patch of the tiny preset (about 5 x 5 x 6 cm around (0, 0.026, 0.02)).
Scene hairScene() {
  HairMesh m = makeGroomPreset("tiny");
  m.strandCount = 4000;
  m.appearance.minHitDiameterPx = 1.0f;
  Scene s;
  s.width = 131;  // not multiples of the 8x8 work-groups
  s.height = 97;
  s.ambient = glm::vec3(0.05f);
  s.grooms.emplace_back("tiny", std::make_shared<const HairMesh>(m));
  s.camera.position = glm::vec3(0.0f, 0.026f, 0.22f);
  s.camera.target = glm::vec3(0.0f, 0.026f, 0.02f);
  s.camera.fovYDegrees = 35.0f;
  return s;
}

RenderOptions gbufferOptions() {
  RenderOptions o;
  o.filter = Toggle::Off;
  o.captureGBuffer = true;
  return o;
}

std::size_t hairPixels(const Frame& f) {
  const std::size_t pixels = f.depth.size();
  std::size_t n = 0;
  for (std::size_t i = 0; i < pixels; ++i) n += f.gbuffer[i] != ~std::uint64_t(0);
  return n;
}

TEST(Mesh, TwoTrianglePlaneHidesHairLikeTheAnalyticPlane) {
  // a tilted plane through the middle of the patch, facing the camera
  const glm::vec3 center(0.0f, 0.026f, 0.02f), normal = glm::normalize(glm::vec3(0.3f, 0.2f, 1.0f));
  Scene bare = hairScene(), analytic = hairScene(), mesh = hairScene();
  Plane p;
  p.normal = normal;
  p.offset = glm::dot(normal, center);
  p.color = glm::vec3(0.4f);
  analytic.planes.push_back(p);
  MeshInstance mi;
  mi.name = "square";
  mi.mesh = squareMesh(center, normal, 2.0f);  // the view is ~0.13 across at the plane
  mi.color = p.color;
  mesh.meshes.push_back(mi);

  Renderer r(test::sharedDevice());
  const Frame fb = r.render(bare, gbufferOptions());
  const Frame fa = r.render(analytic, gbufferOptions());
  const Frame fm = r.render(mesh, gbufferOptions());
  const std::size_t pixels = fa.depth.size();
  ASSERT_EQ(fm.depth.size(), pixels);

  // the plane hides a real share of the hair: the comparison below is not trivially met
  const std::size_t nBare = hairPixels(fb), nAnalytic = hairPixels(fa), nMesh = hairPixels(fm);
  RecordProperty("hair_pixels_bare", std::to_string(nBare));
  RecordProperty("hair_pixels_analytic", std::to_string(nAnalytic));
  RecordProperty("hair_pixels_mesh", std::to_string(nMesh));
  ASSERT_GT(nBare, pixels / 10);
  ASSERT_LT(nAnalytic, nBare * 8 / 10) << "the analytic plane should hide part of the hair";
  ASSERT_GT(nAnalytic, nBare * 2 / 10) << "the analytic plane should leave part of the hair";

  std::size_t sameWord = 0, hairEither = 0, sameDepth = 0, meshDrawn = 0;
  for (std::size_t i = 0; i < pixels; ++i) {
    if (fa.gbuffer[i] != ~std::uint64_t(0) || fm.gbuffer[i] != ~std::uint64_t(0)) {
      ++hairEither;
      sameWord += fa.gbuffer[i] == fm.gbuffer[i];
    }
    const float a = fa.depth[i], m = fm.depth[i];
    sameDepth += std::isfinite(a) && std::isfinite(m) && std::fabs(a - m) <= 1e-5f * a;
    meshDrawn += std::isfinite(m);
  }
  RecordProperty("same_word", std::to_string(sameWord));
  RecordProperty("same_depth", std::to_string(sameDepth));
  EXPECT_EQ(meshDrawn, pixels) << "the square covers the whole view";
  std::printf(
      "[ mesh     ] hair pixels: no plane %zu, analytic plane %zu, mesh plane %zu; same word on "
      "%zu of %zu\n",
      nBare, nAnalytic, nMesh, sameWord, hairEither);
  EXPECT_GE(sameWord, hairEither * 995 / 1000)
      << "hair G-buffer words differ on " << hairEither - sameWord << " of " << hairEither
      << " hair pixels";
  EXPECT_GE(sameDepth, pixels * 995 / 1000)
      << "depth differs on " << pixels - sameDepth << " of " << pixels;
  // the colour of the plane itself matches too where no hair is in front (Lambert, no lights:
  // ambient x albedo on both)
  std::size_t sameColor = 0, planeOnly = 0;
  for (std::size_t i = 0; i < pixels; ++i) {
    if (fa.gbuffer[i] != ~std::uint64_t(0) || fm.gbuffer[i] != ~std::uint64_t(0)) continue;
    ++planeOnly;
    sameColor += std::fabs(fa.color.rgba[4 * i] - fm.color.rgba[4 * i]) <= 1e-5f;
  }
  EXPECT_EQ(sameColor, planeOnly);
}

// Hair lit from above and in front, with or without a horizontal occluder at y = 0.09.
// occluder: 0 none, 1 a two-triangle mesh, 2 an analytic plane; lightIntensity 0 gives the
// frame without the light (ambient only).
Scene shadowScene(int occluder, float lightIntensity = 3.0f) {
  Scene s = hairScene();
  s.ambient = glm::vec3(0.005f);
  s.background = glm::vec3(0.0f);
  Light l;
  l.type = Light::Type::Directional;
  l.direction = glm::normalize(glm::vec3(0.2f, 1.0f, 0.6f));
  l.intensity = lightIntensity;
  l.shadows = true;
  s.lights.push_back(l);
  const glm::vec3 center(0.0f, 0.09f, 0.02f), up(0.0f, 1.0f, 0.0f);
  if (occluder == 1) {
    MeshInstance mi;
    mi.name = "ceiling";
    mi.mesh = squareMesh(center, up, 2.0f);
    s.meshes.push_back(mi);
  } else if (occluder == 2) {
    Plane p;
    p.normal = up;
    p.offset = center.y;
    s.planes.push_back(p);
  }
  return s;
}

TEST(Mesh, MeshCastsIntoTheDeepOpacityMaps) {
  Renderer r(test::sharedDevice());
  const Frame lit = r.render(shadowScene(0), gbufferOptions());
  const Frame meshShadow = r.render(shadowScene(1), gbufferOptions());
  const Frame planeShadow = r.render(shadowScene(2), gbufferOptions());
  const Frame unlit = r.render(shadowScene(0, 0.0f), gbufferOptions());
  const std::size_t pixels = lit.depth.size();
  double sumLit = 0, sumMesh = 0, sumPlane = 0, sumUnlit = 0;
  std::size_t n = 0, close = 0;
  for (std::size_t i = 0; i < pixels; ++i) {
    // hair pixels of all three frames (the occluder is above the hair: it hides none)
    if (lit.gbuffer[i] == ~std::uint64_t(0) || meshShadow.gbuffer[i] == ~std::uint64_t(0) ||
        planeShadow.gbuffer[i] == ~std::uint64_t(0))
      continue;
    ++n;
    double dmax = 0;
    for (int c = 0; c < 3; ++c) {
      sumLit += lit.color.rgba[4 * i + c];
      sumMesh += meshShadow.color.rgba[4 * i + c];
      sumPlane += planeShadow.color.rgba[4 * i + c];
      sumUnlit += unlit.color.rgba[4 * i + c];
      const float d =
          std::fabs(meshShadow.color.rgba[4 * i + c] - planeShadow.color.rgba[4 * i + c]);
      dmax = std::max(dmax, static_cast<double>(d));
    }
    close += dmax <= 1e-4;
  }
  ASSERT_GT(n, pixels / 10);
  RecordProperty("mean_lit", std::to_string(sumLit / n));
  RecordProperty("mean_mesh_occluder", std::to_string(sumMesh / n));
  RecordProperty("mean_plane_occluder", std::to_string(sumPlane / n));
  RecordProperty("mean_unlit", std::to_string(sumUnlit / n));
  // what the light adds: a real share of the lit frame, and (almost) none under an occluder
  const double light = sumLit - sumUnlit;
  ASSERT_GT(light, 0.3 * sumLit)
      << "the light hardly lights the hair: the test would prove nothing";
  EXPECT_LT(sumMesh - sumUnlit, 0.05 * light)
      << "hair under the mesh occluder is not in its shadow";
  EXPECT_LT(sumPlane - sumUnlit, 0.05 * light)
      << "hair under the analytic occluder is not in its shadow";
  EXPECT_GE(close, n * 995 / 1000) << "mesh and analytic occluders shade " << n - close << " of "
                                   << n << " hair pixels differently";
}

TEST(Mesh, ObjReaderSplitsPolygonsAndResolvesRelativeIndices) {
  const std::string dir = test::scratchDir();
  // a quad with 1-based indices, then a triangle with negative (relative) ones and slashes
  writeText(dir + "/ok.obj",
            "# comment\nmtllib none.mtl\no thing\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\n"
            "f 1//1 2//1 3//1 4//1\nv 2 0 0\nv 2 1 0 1.0\nf -3 -2 -1\n");
  const TriangleMesh m = loadTriangleMesh(dir + "/ok.obj");
  EXPECT_EQ(m.name, "ok");
  ASSERT_EQ(m.positions.size(), 6u);
  ASSERT_EQ(m.indices.size(), 9u);
  EXPECT_EQ(m.indices[6], 3u);
  EXPECT_EQ(m.indices[7], 4u);
  EXPECT_EQ(m.indices[8], 5u);
  EXPECT_EQ(m.positions[5], glm::vec3(2, 1, 0));
}

TEST(Mesh, TriangleLimitIsCheckedBeforeParsing) {
  const std::string dir = test::scratchDir();
  writeText(dir + "/five.obj",
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\nf 1 2 3\nf 1 2 3\nf 1 2 3\nf 1 2 3\n");
  MeshLimits limits;
  limits.maxTriangles = 4;
  try {
    loadTriangleMesh(dir + "/five.obj", limits);
    FAIL() << "five triangles passed a limit of four";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("line 8"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("limit is 4"), std::string::npos) << e.what();
  }
  limits.maxTriangles = 5;
  EXPECT_EQ(loadTriangleMesh(dir + "/five.obj", limits).indices.size(), 15u);
  // and the device's largest allocation: 3 vertices x 16 bytes
  limits.maxBufferBytes = 47;
  EXPECT_THROW(loadTriangleMesh(dir + "/five.obj", limits), Error);
}

TEST(Mesh, SceneReadsMeshesRelativeToTheSceneWithScaleAndUpAxis) {
  const std::string dir = test::scratchDir();
  fs::create_directories(dir + "/sub");
  writeText(dir + "/sub/tri.obj", "v 0 0 0\nv 100 0 0\nv 0 0 100\nf 1 2 3\n");
  writeText(
      dir + "/scene.json",
      json{{"meshes",
            {{{"file", "sub/tri.obj"}, {"scale", 0.01}, {"up", "z"}, {"color", {0.2, 0.3, 0.4}}}}}}
          .dump());
  const Scene s = loadScene(dir + "/scene.json");
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.meshes[0].name, "tri");
  EXPECT_EQ(s.meshes[0].color, glm::vec3(0.2f, 0.3f, 0.4f));
  // z up: file (0, 0, 100) cm is 1 m up
  const glm::vec3 top = glm::vec3(s.meshes[0].transform * glm::vec4(0, 0, 100, 1));
  EXPECT_NEAR(top.x, 0.0f, 1e-6f);
  EXPECT_NEAR(top.y, 1.0f, 1e-6f);
  EXPECT_NEAR(top.z, 0.0f, 1e-6f);
}

// ---- the CLI refuses malformed mesh files ---------------------------------------------------

// Writes a scene naming `meshFile` (relative), renders it and expects exit 1, one error
// line naming the scene and the mesh plus every fragment, and no output file.
void expectMeshRefused(const std::string& dir, const std::string& meshFile,
                       const std::vector<std::string>& fragments) {
  const json scene{{"resolution", {64, 48}},
                   {"camera", {{"position", {0.0, 0.03, 0.2}}, {"target", {0.0, 0.025, 0.0}}}},
                   {"meshes", {{{"file", meshFile}}}},
                   {"grooms", {{{"file", test::assetPath("grooms/tiny.hairmesh.json")}}}}};
  writeText(dir + "/scene.json", scene.dump(2));
  const std::string out = dir + "/out.png";
  const test::CommandResult r =
      test::runCli("render " + test::quote(dir + "/scene.json") + " -o " + test::quote(out));
  SCOPED_TRACE("output was:\n" + r.output);
  EXPECT_EQ(r.exitCode, 1);
  const std::string line = test::onlyErrorLine(r.output);
  EXPECT_NE(line.find("scene.json: mesh \"" + meshFile + "\""), std::string::npos) << line;
  for (const std::string& f : fragments)
    EXPECT_NE(line.find(f), std::string::npos) << "lacks \"" << f << "\": " << line;
  const std::size_t end = r.output.find('\n', r.output.find("clhair: error:"));
  if (end != std::string::npos) {
    EXPECT_TRUE(std::all_of(r.output.begin() + static_cast<std::ptrdiff_t>(end), r.output.end(),
                            [](unsigned char c) { return std::isspace(c); }))
        << "the error spans more than one line";
  }
  EXPECT_FALSE(fs::exists(out)) << "an output file was written although the command failed";
}

TEST(MeshCli, TruncatedObj) {
  const std::string dir = test::scratchDir();
  writeText(dir + "/cut.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nv 0.5 0.");  // cut inside a vertex
  expectMeshRefused(dir, "cut.obj", {"line 5", "truncated"});
}

TEST(MeshCli, TruncatedFace) {
  const std::string dir = test::scratchDir();
  writeText(dir + "/cutface.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2");
  expectMeshRefused(dir, "cutface.obj", {"line 5", "2 vertices"});
}

TEST(MeshCli, NanVertex) {
  const std::string dir = test::scratchDir();
  writeText(dir + "/nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n");
  expectMeshRefused(dir, "nan.obj", {"line 2", "vertex 2", "non-finite"});
}

TEST(MeshCli, OverflowingVertex) {
  const std::string dir = test::scratchDir();
  writeText(dir + "/big.obj", "v 0 0 0\nv 1 0 1e39\nv 0 1 0\nf 1 2 3\n");
  expectMeshRefused(dir, "big.obj", {"line 2", "non-finite"});
}

TEST(MeshCli, IndexOutOfRange) {
  const std::string dir = test::scratchDir();
  writeText(dir + "/oor.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 7\n");
  expectMeshRefused(dir, "oor.obj", {"line 5", "face index 7", "3 vertices"});
}

TEST(MeshCli, NegativeIndexOutOfRange) {
  const std::string dir = test::scratchDir();
  writeText(dir + "/neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n");
  expectMeshRefused(dir, "neg.obj", {"line 4", "-4"});
}

TEST(MeshCli, HugeFile) {
  // a sparse file: its size is refused before a byte of it is read
  const std::string dir = test::scratchDir();
  {
    std::ofstream f(dir + "/huge.obj", std::ios::binary);
    f << "v 0 0 0\n";
  }
  fs::resize_file(dir + "/huge.obj", kMaxMeshFileBytes + 1);
  expectMeshRefused(dir, "huge.obj", {"MiB", "decimate"});
  fs::remove(dir + "/huge.obj");
}

TEST(MeshCli, MissingFile) {
  const std::string dir = test::scratchDir();
  expectMeshRefused(dir, "no_such_head.obj", {"does not exist"});
}

TEST(MeshCli, NoFaces) {
  const std::string dir = test::scratchDir();
  writeText(dir + "/points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  expectMeshRefused(dir, "points.obj", {"no faces"});
}

TEST(MeshCli, BinaryAndPlyRefused) {
  const std::string dir = test::scratchDir();
  writeText(dir + "/head.ply", "ply\nformat ascii 1.0\nend_header\n");
  expectMeshRefused(dir, "head.ply", {"PLY", "not supported", "OBJ"});
  writeText(dir + "/bin.obj", std::string("v 0 0 0\n\0\1\2", 11));
  expectMeshRefused(dir, "bin.obj", {"binary"});
}

}  // namespace
}  // namespace clhair
