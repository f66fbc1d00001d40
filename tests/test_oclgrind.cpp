// test_oclgrind.cpp — the `clhair` CLI under Oclgrind (--data-races --uninitialized
// --check-api, plus its always-on memory checks) over every kernel of a frame and of the
// strand export, on a tiny groom: zero reports.
//
// Inputs: tests/data/oclgrind_tiny.json (48x32, one sphere, one shadowed light, the tiny
// groom, whose AO is baked on load) and assets/grooms/tiny.hairmesh.json. The runs that do not
// check the AO bake load the tiny groom with its AO baked beforehand (bakedTinyGroom). Oclgrind
// intercepts the OpenCL API, so the CLI sees a single device, "Oclgrind Simulator" (OpenCL 1.2 with
// 64-bit atomics, local sub-group backend); --inst-counts proves that each expected kernel ran.
// Diagnostics go to a log file
// (--log) that must hold no report. Oclgrind exits 0 even when it reports, hence the log.
//
// Each command runs twice:
//  - as built (optimised), with --data-races --check-api. Not --uninitialized: Oclgrind
//    21.10 crashes (SIGSEGV in Uninitialized::instructionExecuted) on a shufflevector whose
//    mask has undef lanes, which clang emits for every float3 -> float4 widening;
//  - with -cl-opt-disable, adding --uninitialized. Unoptimised code also avoids the false
//    "uninitialized value written" that clang's split of a uint4 store (a whole-vector store
//    of <poison, poison, poison, 0> followed by per-lane stores) triggers in lod_bundles.
// Both pass -DCLH_ATOMIC_LOAD_SKIP=0 through Oclgrind's --build-options: the plain load
// before atom_min in strands_raster is a deliberate, benign race (DESIGN.md, Atomics) that
// Oclgrind reports as a read-write data race; switching it off checks everything else.
// They also pass -DAO_DIRS=8: the AO bakes (ao_bake per layer vertex, ao_field per voxel)
// march 8 directions instead of 64, the same loop body eight times fewer, which was most of
// the simulated instructions of a frame that bakes (69 % of the strand file's unoptimised run).
// One more optimised run keeps the load skip, as shipped, and accepts those races alone
// (OclgrindLoadSkip).
//
// The renderer clears the G-buffer with a kernel (clear.cl), not clEnqueueFillBuffer, whose
// memory Oclgrind 21.10 would treat as uninitialised.
// The frame's filter is the default one, Huang's (identity layer, linking with its curve
// pass, alpha fix, anisotropic filter); Lipp's runs once more over the same scene,
// optimised only (OclgrindLipp).
// Skipped, with the reason, when oclgrind is not installed.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "test_util.h"

namespace clhair::test {
namespace {

namespace fs = std::filesystem;

// A path as a JSON string (the test folders have no quotes or backslashes; checked).
std::string jsonString(const std::string& s) {
  EXPECT_EQ(s.find_first_of("\"\\"), std::string::npos) << s;
  return "\"" + s + "\"";
}

bool haveOclgrind() { return runCommand("command -v oclgrind >/dev/null").exitCode == 0; }

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// One Oclgrind diagnostic: its first line ("Read-write data race at ...", "Invalid read of
// size 8 ...", "Oclgrind - OpenCL runtime error detected", ...) and the indented lines below.
struct Report {
  std::string header;
  std::string kernel;  // from "\tKernel: name", empty for API errors
  std::string text;
};

// Splits an Oclgrind log into reports: each starts at a non-empty line that is not indented.
std::vector<Report> parseReports(const std::string& log) {
  std::vector<Report> out;
  std::istringstream in(log);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line[0] != '\t' && line[0] != ' ') {
      out.push_back({line, "", ""});
    } else if (out.empty()) {
      out.push_back({"(indented text without a header)", "", ""});
    }
    Report& r = out.back();
    r.text += line + "\n";
    const std::string tag = "\tKernel:";
    if (r.kernel.empty() && line.compare(0, tag.size(), tag) == 0) {
      std::string k = line.substr(tag.size());
      k.erase(0, k.find_first_not_of(" \t"));
      r.kernel = k;
    }
  }
  return out;
}

// Words of Oclgrind's diagnostics (found by provoking each one in a scratch program); the
// CLI's own output never contains them.
const char* const kMarkers[] = {"data race",        "Invalid read",        "Invalid write",
                                "Invalid memory",   "Uninitialized value", "Uninitialized address",
                                "on uninitialized", "Unaligned address",   "divergence",
                                "runtime error",    "errors generated",    "\tKernel:",
                                "Oclgrind: "};

struct OclgrindRun {
  CommandResult result;
  std::string log;
  double seconds = 0.0;
};

// `cacheTag`: the program cache's name when not the tag's own (runs of the same build options
// may share one: the second loads the programs and the AO field from it).
OclgrindRun runUnderOclgrind(const std::string& dir, const std::string& tag, bool uninitialized,
                             const std::string& cliArgs, const std::string& cacheTag = "") {
  const std::string logPath = dir + "/oclgrind-" + tag + ".log";
  std::string buildOptions = "-DCLH_ATOMIC_LOAD_SKIP=0 -DAO_DIRS=8";
  std::string flags = "--data-races --check-api --inst-counts --max-errors 1000000";
  if (uninitialized) {
    buildOptions = "-cl-opt-disable " + buildOptions;
    flags += " --uninitialized";
  }
  // A program cache of this run's own: Oclgrind adds --build-options behind the CLI's back,
  // so the cache key cannot tell an -cl-opt-disable build from an optimised one, and an
  // optimised binary cached by an earlier run crashes Oclgrind's --uninitialized checks.
  const std::string cache = dir + "/clhair-cache-" + (cacheTag.empty() ? tag : cacheTag);
  std::string cmd = "CLHAIR_CACHE_DIR=" + quote(cache) + " oclgrind " + flags +
                    " --build-options " + quote(buildOptions) + " --log " + quote(logPath) + " " +
                    quote(cliPath()) + " " + cliArgs;
  OclgrindRun run;
  auto t0 = std::chrono::steady_clock::now();
  run.result = runCommand(cmd);
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  run.log = readFile(logPath);
  std::printf("[ oclgrind ] %s: %.1f s\n", tag.c_str(), run.seconds);
  return run;
}

// Asserts a clean run: exit 0, every expected kernel executed, no report.
void expectClean(const OclgrindRun& run, const std::vector<std::string>& kernels,
                 const std::string& what) {
  ASSERT_EQ(run.result.exitCode, 0) << what << " failed under oclgrind:\n" << run.result.output;
  for (const std::string& k : kernels)
    EXPECT_NE(run.result.output.find("Instructions executed for kernel '" + k + "'"),
              std::string::npos)
        << what << ": kernel " << k << " did not run under oclgrind\n"
        << run.result.output;

  std::string kept;
  for (const Report& r : parseReports(run.log)) kept += r.text + "\n";
  EXPECT_TRUE(kept.empty()) << what << ": oclgrind reported:\n" << kept.substr(0, 20000);
  for (const char* m : kMarkers)
    EXPECT_EQ(run.result.output.find(m), std::string::npos)
        << what << ": the command output holds oclgrind's \"" << m << "\":\n"
        << run.result.output;
}

const std::vector<std::string> kFrameKernels = {
    "opaque_render",        "lod_bundles",  "scan_bundles",    "clear_words",
    "strands_raster",       "link_select",  "link_propagate",  "link_merge",
    "link_alpha",           "link_aniso",   "shade_deferred",  "composite_over",
    "shadow_resolve_depth", "shadow_clear", "strands_opacity", "ao_clear",
    "ao_voxelize",          "ao_bake"};
const std::vector<std::string> kExportKernels = {"lod_bundles", "scan_bundles", "strands_export"};

// oclgrind_tiny.json as a scene written to another folder: its groom by absolute path (`groom`,
// else the tiny groom of assets/), and `before` inserted ahead of its "grooms" key; empty if
// the file lost either line.
std::string tinySceneWith(const std::string& before, const std::string& groom = "") {
  std::ifstream in(sourceDir() + "/tests/data/oclgrind_tiny.json");
  std::string scene((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string from = "\"../../assets/grooms/tiny.hairmesh.json\"";
  const std::size_t at = scene.find("\"grooms\": ["), g = scene.find(from);
  if (at == std::string::npos || g == std::string::npos || g < at) return {};
  scene.replace(g, from.size(),
                jsonString(groom.empty() ? assetPath("grooms/tiny.hairmesh.json") : groom));
  return scene.insert(at, before);
}

// The tiny groom with its AO baked beforehand (clhair bake-ao on the default device, not
// under Oclgrind), in `dir`: loading it runs no bake. The bake (its export, grid clear and
// ao_bake) is about half of a frame's simulated instructions, so only the runs that check it
// (Oclgrind.RenderTinyGroomHasNoReports, OclgrindLoadSkip) load the groom without AO.
std::string bakedTinyGroom(const std::string& dir) {
  const std::string out = dir + "/tiny.baked.hairmesh.json";
  const CommandResult r =
      runCli("bake-ao " + quote(assetPath("grooms/tiny.hairmesh.json")) + " -o " + quote(out));
  EXPECT_EQ(r.exitCode, 0) << r.output;
  return out;
}

// tinySceneWith(before) on the baked tiny groom, written to dir/scene.json; its path, or ""
// (with a failure) when oclgrind_tiny.json lost its grooms lines.
std::string bakedTinyScene(const std::string& dir, const std::string& before = "") {
  const std::string scene = tinySceneWith(before, bakedTinyGroom(dir));
  EXPECT_FALSE(scene.empty()) << "tests/data/oclgrind_tiny.json changed its grooms lines";
  if (scene.empty()) return {};
  std::ofstream(dir + "/scene.json") << scene;
  return dir + "/scene.json";
}

class Oclgrind : public ::testing::TestWithParam<bool> {};  // param: --uninitialized

TEST_P(Oclgrind, RenderTinyGroomHasNoReports) {
  if (!haveOclgrind()) GTEST_SKIP() << "oclgrind not installed";
  const bool uninit = GetParam();
  const std::string dir = scratchDir();
  const std::string scene = sourceDir() + "/tests/data/oclgrind_tiny.json";
  const std::string out = dir + "/tiny.png";
  OclgrindRun run = runUnderOclgrind(dir, uninit ? "render-uninit" : "render", uninit,
                                     "render " + quote(scene) + " -o " + quote(out));
  expectClean(run, kFrameKernels, "clhair render");
  EXPECT_TRUE(fs::exists(out)) << out << " was not written";
  // Oclgrind replaces the OpenCL library, so its simulator is the only device to choose.
  EXPECT_NE(run.result.output.find("on Oclgrind Simulator"), std::string::npos)
      << run.result.output;
}

// Lipp's filter (filter_reconstruct), no longer the default of a frame of one view.
TEST(OclgrindLipp, RenderWithLippsFilterHasNoReports) {
  if (!haveOclgrind()) GTEST_SKIP() << "oclgrind not installed";
  const std::string dir = scratchDir();
  const std::string scene = bakedTinyScene(dir);
  ASSERT_FALSE(scene.empty());
  const std::string out = dir + "/tiny.png";
  OclgrindRun run = runUnderOclgrind(dir, "lipp", false,
                                     "render " + quote(scene) + " --filter lipp -o " + quote(out));
  expectClean(run, {"strands_raster", "shade_deferred", "filter_reconstruct", "composite_over"},
              "clhair render --filter lipp");
  EXPECT_TRUE(fs::exists(out)) << out << " was not written";
}

TEST_P(Oclgrind, RenderWithLodMsaaAndPersistentGridHasNoReports) {
  if (!haveOclgrind()) GTEST_SKIP() << "oclgrind not installed";
  const bool uninit = GetParam();
  const std::string dir = scratchDir();
  const std::string scene = bakedTinyScene(dir);
  ASSERT_FALSE(scene.empty());
  const std::string out = dir + "/tiny-msaa.png";
  OclgrindRun run = runUnderOclgrind(
      dir, uninit ? "render-lod-uninit" : "render-lod", uninit,
      "render " + quote(scene) + " -o " + quote(out) + " --lod on --msaa 4 --dispatch persistent");
  expectClean(run, {"lod_bundles", "scan_bundles", "strands_raster_persistent", "shade_deferred"},
              "clhair render --lod on --msaa 4 --dispatch persistent");
  EXPECT_TRUE(fs::exists(out)) << out << " was not written";
}

TEST(OclgrindAggregate, RenderWithTheAggregatedLodBsdfHasNoReports) {
  // LOD strands shaded with the aggregated BCSDF (Huang 2024, hair_bsdf.h): far and 128x96,
  // where LOD draws 19 of the 61 strands and the hair still covers pixel centres (the frame
  // differs from the single-fibre one); as two passes of final, whose strands are stored
  // once (strands_store) and drawn from there (strands_raster_stored)
  if (!haveOclgrind()) GTEST_SKIP() << "oclgrind not installed";
  const std::string dir = scratchDir();
  const std::string scene = bakedTinyScene(dir);
  ASSERT_FALSE(scene.empty());
  const std::string out = dir + "/tiny-aggregate.png";
  OclgrindRun run =
      runUnderOclgrind(dir, "render-aggregate", false,
                       "render " + quote(scene) + " -o " + quote(out) +
                           " --camera far --width 128 --height 96 --lod on --lod-bsdf aggregated" +
                           " --quality final --spp 2");
  expectClean(
      run,
      {"lod_bundles", "scan_bundles", "strands_store", "strands_raster_stored", "shade_deferred"},
      "clhair render --camera far --lod on --lod-bsdf aggregated --quality final");
  EXPECT_TRUE(fs::exists(out)) << out << " was not written";
}

TEST_P(Oclgrind, RenderInCoverageModeHasNoReports) {
  // the coverage raster (trapezoids, chained layers, coverage plane) and its shading
  if (!haveOclgrind()) GTEST_SKIP() << "oclgrind not installed";
  const bool uninit = GetParam();
  const std::string dir = scratchDir();
  const std::string scene = bakedTinyScene(dir);
  ASSERT_FALSE(scene.empty());
  const std::string out = dir + "/tiny-coverage.png";
  OclgrindRun run =
      runUnderOclgrind(dir, uninit ? "render-coverage-uninit" : "render-coverage", uninit,
                       "render " + quote(scene) + " -o " + quote(out) + " --raster coverage");
  expectClean(run, {"lod_bundles", "strands_raster", "shade_deferred", "composite_over"},
              "clhair render --raster coverage");
  EXPECT_TRUE(fs::exists(out)) << out << " was not written";
}

TEST_P(Oclgrind, ExportStrandsHasNoReports) {
  if (!haveOclgrind()) GTEST_SKIP() << "oclgrind not installed";
  const bool uninit = GetParam();
  const std::string dir = scratchDir();
  const std::string out = dir + "/tiny.hair";
  OclgrindRun run =
      runUnderOclgrind(dir, uninit ? "export-uninit" : "export", uninit,
                       "export-strands " + quote(bakedTinyGroom(dir)) + " -o " + quote(out));
  expectClean(run, kExportKernels, "clhair export-strands");
  EXPECT_TRUE(fs::exists(out)) << out << " was not written";
}

// An explicit strand groom (kernels/strands_explicit.cl): the tiny groom's strands written to
// a .hair file (export-strands, not under Oclgrind) and rendered in the scene of
// oclgrind_tiny.json with LOD on; optimised, once more with MSAA 4 on the persistent grid (from
// the first run's program cache, which holds its AO field too).
TEST_P(Oclgrind, RenderStrandFileHasNoReports) {
  if (!haveOclgrind()) GTEST_SKIP() << "oclgrind not installed";
  const bool uninit = GetParam();
  const std::string dir = scratchDir();
  CommandResult ex = runCli("export-strands " + quote(assetPath("grooms/tiny.hairmesh.json")) +
                            " -o " + quote(dir + "/tiny.hair"));
  ASSERT_EQ(ex.exitCode, 0) << ex.output;
  {
    std::ifstream in(sourceDir() + "/tests/data/oclgrind_tiny.json");
    std::string scene((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string from = "{\"file\": \"../../assets/grooms/tiny.hairmesh.json\"}";
    const std::size_t at = scene.find(from);
    ASSERT_NE(at, std::string::npos) << "tests/data/oclgrind_tiny.json changed its groom line";
    scene.replace(at, from.size(),
                  "{\"strands_file\": \"tiny.hair\", \"lod\": {\"enabled\": true}}");
    std::ofstream(dir + "/scene.json") << scene;
  }
  const std::string out = dir + "/strands.png";
  OclgrindRun run = runUnderOclgrind(dir, uninit ? "strands-uninit" : "strands", uninit,
                                     "render " + quote(dir + "/scene.json") + " -o " + quote(out));
  expectClean(run,
              {"lod_chunks", "scan_bundles", "strands_explicit_raster", "strands_explicit_opacity"},
              "clhair render (strand file)");
  EXPECT_TRUE(fs::exists(out)) << out << " was not written";
  if (uninit) return;
  OclgrindRun grid =
      runUnderOclgrind(dir, "strands-persistent", false,
                       "render " + quote(dir + "/scene.json") + " -o " + quote(dir + "/grid.png") +
                           " --msaa 4 --dispatch persistent",
                       "strands");
  expectClean(grid, {"lod_chunks", "strands_explicit_raster_persistent"},
              "clhair render (strand file) --msaa 4 --dispatch persistent");
}

// Several views of one assembly (strands_raster_views: every strand drawn into both views'
// G-buffers, side by side in one buffer): the scene of oclgrind_tiny.json as a stereo pair
// 6 mm apart. Optimised only, for the suite's time. The -cl-opt-disable --uninitialized run
// reported "control flow depends on uninitialized value" in strands_raster_views at the scene
// depth test (raster_core.h) while the host copied each view's depth into the shared buffer
// with clEnqueueCopyBuffer; since each view's opaque pass writes its slice in place (a
// sub-buffer), that run is clean (by hand: 3741 reports before, none after).
TEST(OclgrindViews, RenderTwoViewsHasNoReports) {
  if (!haveOclgrind()) GTEST_SKIP() << "oclgrind not installed";
  const std::string dir = scratchDir();
  const std::string scene = tinySceneWith(
      "\"cameras\": [{\"name\": \"left\", \"offset\": [-0.003, 0, 0]}, "
      "{\"name\": \"right\", \"offset\": [0.003, 0, 0]}],\n  ",
      bakedTinyGroom(dir));
  ASSERT_FALSE(scene.empty()) << "tests/data/oclgrind_tiny.json changed its grooms lines";
  std::ofstream(dir + "/scene.json") << scene;
  OclgrindRun run =
      runUnderOclgrind(dir, "views", false,
                       "render " + quote(dir + "/scene.json") + " -o " + quote(dir + "/two.png"));
  expectClean(run, {"strands_raster_views", "shade_deferred", "composite_over"},
              "clhair render (two views)");
  for (const char* f : {"two.left.png", "two.right.png"})
    EXPECT_TRUE(fs::exists(dir + "/" + f)) << f << " was not written";
}

// Triangle meshes (kernels/mesh.cl): the scene of oclgrind_tiny.json plus the example head
// (assets/meshes/head.obj, 2976 triangles, scaled to the sphere's size) and a two-triangle
// floor larger than the view, from the camera and from the shadowed light.
TEST_P(Oclgrind, RenderMeshHasNoReports) {
  if (!haveOclgrind()) GTEST_SKIP() << "oclgrind not installed";
  const bool uninit = GetParam();
  const std::string dir = scratchDir();
  {
    const std::string scene = tinySceneWith(
        "\"meshes\": [{\"file\": " + jsonString(assetPath("meshes/head.obj")) +
            ", \"scale\": 0.0018, \"up\": \"z\", \"transform\": {\"translate\": [0.0, "
            "-0.01, 0.0]}}, "
            "{\"file\": \"floor.obj\", \"color\": [0.3, 0.3, 0.3]}],\n  ",
        bakedTinyGroom(dir));
    ASSERT_FALSE(scene.empty()) << "tests/data/oclgrind_tiny.json changed its grooms lines";
    std::ofstream(dir + "/scene.json") << scene;
    std::ofstream(dir + "/floor.obj")
        << "v -5 -0.03 -5\nv 5 -0.03 -5\nv 5 -0.03 5\nv -5 -0.03 5\nf 1 2 3 4\n";
  }
  const std::string out = dir + "/mesh.png";
  OclgrindRun run = runUnderOclgrind(dir, uninit ? "mesh-uninit" : "mesh", uninit,
                                     "render " + quote(dir + "/scene.json") + " -o " + quote(out));
  expectClean(run, {"opaque_render", "mesh_raster", "mesh_resolve"}, "clhair render (meshes)");
  EXPECT_TRUE(fs::exists(out)) << out << " was not written";
}

// The export variant of the explicit kernel through this test binary's own
// ExplicitKernel tests (test_explicit.cpp: strands of 2..300 points, several 128-segment
// rounds, point skipping, vertex-LOD morph), which also check it against the CPU reference;
// unoptimised, only the point-skipping and morph test (the slow simulation).
TEST_P(Oclgrind, ExplicitStrandExportHasNoReports) {
  if (!haveOclgrind()) GTEST_SKIP() << "oclgrind not installed";
  const bool uninit = GetParam();
  const std::string dir = scratchDir();
  const std::string logPath = dir + "/oclgrind-explicit-export.log";
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  OclgrindRun run;
  run.result =
      runCommand("oclgrind --data-races --check-api --inst-counts --max-errors 1000000" +
                 std::string(uninit ? " --uninitialized" : "") + " --build-options " +
                 quote(std::string(uninit ? "-cl-opt-disable " : "") + "-DCLH_ATOMIC_LOAD_SKIP=0") +
                 " --log " + quote(logPath) + " " + quote(self) + " --gtest_filter=" +
                 quote(uninit ? "ExplicitKernel.PointSkipping*" : "ExplicitKernel.*"));
  run.log = readFile(logPath);
  // Not the exit code: a test binary under Oclgrind 21.10 aborts after its last test while
  // static objects are destroyed (the shared Device outlives Oclgrind's runtime; any test
  // does it, e.g. Render.EmptySceneIsExactlyTheBackground), which is not a kernel report.
  EXPECT_NE(run.result.output.find(uninit ? "[  PASSED  ] 1 test" : "[  PASSED  ] 2 tests"),
            std::string::npos)
      << run.result.output;
  EXPECT_NE(run.result.output.find("Instructions executed for kernel 'strands_explicit_export'"),
            std::string::npos)
      << run.result.output;
  std::string kept;
  for (const Report& r : parseReports(run.log)) kept += r.text + "\n";
  EXPECT_TRUE(kept.empty()) << "oclgrind reported:\n" << kept.substr(0, 20000);
}

// The line numbers of kernels/include/clhair/raster_core.h that hold `needle`.
std::set<int> rasterCoreLines(const std::string& needle) {
  std::ifstream in(sourceDir() + "/kernels/include/clhair/raster_core.h");
  std::set<int> lines;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n)
    if (line.find(needle) != std::string::npos) lines.insert(n);
  return lines;
}

// The lines named by a report's "At line N (column C) of FILE:" entries.
std::vector<std::pair<int, std::string>> reportLines(const std::string& text) {
  std::vector<std::pair<int, std::string>> out;
  const std::string tag = "At line ";
  for (std::size_t at = text.find(tag); at != std::string::npos; at = text.find(tag, at + 1)) {
    const int line = std::atoi(text.c_str() + at + tag.size());
    const std::size_t of = text.find(" of ", at), colon = text.find(":\n", at);
    const bool named = of != std::string::npos && colon != std::string::npos;
    out.emplace_back(line, named ? text.substr(of + 4, colon - of - 4) : "");
  }
  return out;
}

// The frame as shipped: the G-buffer writes keep their plain load before atom_min (the load
// skip, CLH_ATOMIC_LOAD_SKIP 1, DESIGN.md "Atomics"), which the runs above switch off. That
// load races with other work-items' atom_min by design (a stale read only costs an
// atomic), and Oclgrind reports each such pair as a read-write data race. Every report must
// be one of those: in a strand raster kernel, between a load-skip line of raster_core.h (`seen
// = gbuf[...]`) and its atom_min line; at least one must be there (the shipped path ran
// under Oclgrind's checks); and the image must equal PoCL's, bit for bit.
TEST(OclgrindLoadSkip, ShippedFrameHasOnlyTheLoadSkipsBenignRaces) {
  if (!haveOclgrind()) GTEST_SKIP() << "oclgrind not installed";
  const std::string dir = scratchDir();
  const std::string scene = sourceDir() + "/tests/data/oclgrind_tiny.json";
  const std::string out = dir + "/tiny.png", pocl = dir + "/pocl.png";
  const std::string logPath = dir + "/oclgrind-load-skip.log";
  OclgrindRun run;
  run.result = runCommand(
      "CLHAIR_CACHE_DIR=" + quote(dir + "/clhair-cache") +
      " oclgrind --data-races --check-api --inst-counts --max-errors 1000000 --log " +
      quote(logPath) + " " + quote(cliPath()) + " render " + quote(scene) + " -o " + quote(out));
  run.log = readFile(logPath);
  ASSERT_EQ(run.result.exitCode, 0) << run.result.output;
  for (const std::string& k : kFrameKernels)
    EXPECT_NE(run.result.output.find("Instructions executed for kernel '" + k + "'"),
              std::string::npos)
        << "kernel " << k << " did not run under oclgrind\n"
        << run.result.output;

  const std::set<int> loads = rasterCoreLines("seen = gbuf[");
  const std::set<int> atomics = rasterCoreLines("atom_min(gbuf");
  ASSERT_FALSE(loads.empty()) << "raster_core.h has no load-skip line any more; update this test";
  ASSERT_EQ(atomics.size(), 1u);
  std::size_t benign = 0;
  std::string kept;
  for (const Report& r : parseReports(run.log)) {
    const auto lines = reportLines(r.text);
    const bool raster = r.kernel.rfind("strands_raster", 0) == 0 ||
                        r.kernel.rfind("strands_explicit_raster", 0) == 0;
    const bool pair = lines.size() == 2 && lines[0].second == "clhair/raster_core.h" &&
                      lines[1].second == "clhair/raster_core.h" &&
                      ((loads.count(lines[0].first) && atomics.count(lines[1].first)) ||
                       (atomics.count(lines[0].first) && loads.count(lines[1].first)));
    if (r.header.rfind("Read-write data race", 0) == 0 && raster && pair)
      ++benign;
    else if (kept.size() < 20000)
      kept += r.text + "\n";
  }
  RecordProperty("load_skip_races", std::to_string(benign));
  EXPECT_GT(benign, 0u)
      << "no race between the load skip and atom_min: the shipped load skip did not run";
  EXPECT_TRUE(kept.empty()) << "oclgrind reported more than the load skip's races:\n" << kept;

  const CommandResult p = runCli("render " + quote(scene) + " -o " + quote(pocl) + " --quiet");
  ASSERT_EQ(p.exitCode, 0) << p.output;
  EXPECT_EQ(readFile(out), readFile(pocl))
      << "Oclgrind's frame differs from PoCL's: " << out << ", " << pocl;
}

INSTANTIATE_TEST_SUITE_P(Checks, Oclgrind, ::testing::Bool(),
                         [](const ::testing::TestParamInfo<bool>& info) {
                           return std::string(info.param ? "OptDisabled_Uninit" : "Optimised");
                         });

}  // namespace
}  // namespace clhair::test
