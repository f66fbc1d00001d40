// test_still_assembly.cpp — a still of quality final assembles each hair mesh's strands once
// (RenderOptions::reuseAssembly, GroomGpu::rasterStill, strands_store and
// strands_raster_stored in kernels/strands.cl): its passes draw byte for byte what passes
// that assemble their strands again draw, with LOD (fewer strands, fewer control points, the
// vertex-LOD morph), with MSAA, on one lane per strand and on 32-lane sub-groups; a pass of a
// still really draws the strands of that still's first pass; and passes of one strand in N
// (RenderOptions::finalSubset) draw disjoint subsets at the coverage of all strands.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <set>

#include "clhair/gpu_types.h"
#include "clhair/progressive.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "groom/presets.h"
#include "test_util.h"

namespace clhair::test {
namespace {

// The tiny preset's 900 strands with LOD, a shadowed light and a sphere, framed at `preset`.
Scene stillScene(CameraPreset preset) {
  HairMesh m = makeGroomPreset("tiny");
  m.strandCount = 900;
  m.lod.enabled = true;
  Scene s;
  s.width = 64;
  s.height = 48;
  s.grooms.emplace_back("tiny", std::make_shared<const HairMesh>(m));
  s.camera = framePreset(s, preset, 30.0f, 15.0f);
  Light l;
  l.direction = glm::normalize(glm::vec3(0.3f, 0.8f, 0.5f));
  l.shadows = true;
  s.lights.push_back(l);
  return s;
}

bool sameBytes(const Frame& a, const Frame& b) {
  return a.color.rgba.size() == b.color.rgba.size() &&
         std::memcmp(a.color.rgba.data(), b.color.rgba.data(), a.color.rgba.size() * 4) == 0;
}

double meanAbsDiff(const Frame& a, const Frame& b) {
  double sum = 0.0;
  for (std::size_t k = 0; k < a.color.rgba.size(); ++k)
    sum += std::fabs(a.color.rgba[k] - b.color.rgba[k]);
  return sum / static_cast<double>(std::max<std::size_t>(a.color.rgba.size(), 1));
}

// final's passes with and without the kept assembly, at three distances (far: LOD draws a
// fraction of the strands with fewer points), one sample per pass and good's MSAA 4 path.
void expectReuseIsExact(Device& device) {
  Renderer r(device);
  for (CameraPreset preset : {CameraPreset::Close, CameraPreset::Mid, CameraPreset::Far}) {
    const Scene s = stillScene(preset);
    for (int path : {0, 1}) {
      SCOPED_TRACE("camera preset " + std::to_string(static_cast<int>(preset)) + ", final path " +
                   std::to_string(path));
      RenderOptions o;
      o.quality = Quality::Final;
      o.spp = 3;
      o.finalPath = path == 1 ? FinalPath::Good : FinalPath::OneSample;
      RenderOptions again = o;
      again.reuseAssembly = false;
      const Frame kept = r.render(s, o), assembled = r.render(s, again);
      EXPECT_TRUE(sameBytes(kept, assembled)) << "mean difference " << meanAbsDiff(kept, assembled);
    }
  }
}

TEST(StillAssembly, PassesDrawWhatAssemblingAgainDraws) { expectReuseIsExact(sharedDevice()); }

// The stored strands are laid out per lane: 32 lanes per strand (the __local sub-group
// backend, what GPUs run) hand each lane the run of points and the neighbours' first point
// and tangent that the assembly's shuffles gave it. The strand pass alone (its G-buffer
// words), near and far, at MSAA 1 (each program built for 32 lanes costs the suite's time;
// MSAA 4 is the full test's).
TEST(StillAssembly, StoredStrandsDrawTheSameWordsOn32Lanes) {
  useTestEnvironment();
  const DeviceInfo& shared = sharedDevice().info();
  DeviceOptions d;
  d.kernelWarningsAsErrors = true;
  d.selector = std::to_string(shared.platformIndex) + ":" + std::to_string(shared.deviceIndex);
  d = DeviceOptions::fromEnvironment(d);
  d.subgroup = "local";
  Renderer r(Device::open(d));
  for (CameraPreset preset : {CameraPreset::Close, CameraPreset::Far}) {
    Scene s = stillScene(preset);
    s.lights[0].shadows = false;
    for (int msaa : {1}) {
      SCOPED_TRACE("camera preset " + std::to_string(static_cast<int>(preset)) + ", MSAA " +
                   std::to_string(msaa));
      RenderOptions o;
      o.msaa = msaa;
      o.rasterOnly = true;
      o.captureGBuffer = true;
      RenderOptions kept = o;
      kept.still = 0x32 + static_cast<std::uint64_t>(msaa) * 3 + static_cast<int>(preset);
      const Frame a = r.render(s, o), b = r.render(s, kept);
      ASSERT_FALSE(a.gbuffer.empty());
      EXPECT_TRUE(a.gbuffer == b.gbuffer);
      EXPECT_GT(a.stats.strandsDrawn, 0u);
    }
  }
}

// A pass of a still draws the strands its first pass kept: a small frame's pass of a still
// begun in a large frame draws the large frame's strands (all 900, thin), not the small
// frame's LOD (fewer, widened); a new still assembles its own.
TEST(StillAssembly, APassDrawsTheStrandsItsStillsFirstPassKept) {
  Renderer r(sharedDevice());
  const Scene small = stillScene(CameraPreset::Far);
  Scene large = small;  // the same hair mesh, so the same groom on the device
  large.width = 640;
  large.height = 480;
  large.camera = framePreset(large, CameraPreset::Close, 30.0f, 15.0f);
  RenderOptions o;
  o.still = 0x5eed;
  const Frame first = r.render(large, o);
  const Frame ofLarge = r.render(small, o);
  RenderOptions own = o;
  own.still = 0;
  const Frame smallOwn = r.render(small, own);
  ASSERT_LT(smallOwn.stats.strandsDrawn, first.stats.strandsDrawn)
      << "the premise: LOD draws fewer strands in the small frame";
  EXPECT_FALSE(sameBytes(ofLarge, smallOwn))
      << "the small frame drew its own LOD's strands, not the kept ones";
  RenderOptions fresh = o;
  fresh.still = 0x5eee;
  EXPECT_TRUE(sameBytes(r.render(small, fresh), smallOwn)) << "a new still keeps its own strands";
}

// Passes of one strand in 3: each draws only strands whose hash plus the pass index is a
// multiple of 3 (read from the identity layer), three passes in a row draw disjoint sets,
// and each covers about as many pixel centres as every strand does (widened threefold).
TEST(StillAssembly, SubsetPassesDrawDisjointThirdsAtTheCoverageOfAll) {
  Renderer r(sharedDevice());
  Scene s = stillScene(CameraPreset::Close);
  s.width = 160;
  s.height = 120;
  s.camera = framePreset(s, CameraPreset::Close, 30.0f, 15.0f);
  RenderOptions o;
  o.rasterOnly = true;
  o.captureGBuffer = true;
  o.strandIds = true;
  o.still = 0x3b;
  const std::size_t pixels = std::size_t(s.width) * s.height;
  auto centres = [&](const Frame& f) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < pixels; ++i) n += f.gbuffer[i] != ~0ull;
    return n;
  };
  const Frame all = r.render(s, o);
  ASSERT_GE(all.gbuffer.size(), 3 * pixels);
  const std::size_t full = centres(all);
  ASSERT_GT(full, 500u);
  std::vector<std::set<std::uint32_t>> seen(3);
  for (int pass = 0; pass < 3; ++pass) {
    SCOPED_TRACE("pass " + std::to_string(pass));
    RenderOptions p = o;
    p.finalSubset = 3;
    p.stillPass = pass;
    const Frame f = r.render(s, p);
    ASSERT_GE(f.gbuffer.size(), 3 * pixels);
    for (std::size_t i = 0; i < pixels; ++i) {
      const std::uint64_t id = f.gbuffer[2 * pixels + i];
      if (id == ~0ull) continue;
      const std::uint32_t strand = gpu::clh_id_strand(id);
      EXPECT_EQ((gpu::clh_hash(strand) + static_cast<std::uint32_t>(pass)) % 3u, 0u) << strand;
      seen[pass].insert(strand);
    }
    EXPECT_GT(seen[pass].size(), 20u);
    const double ratio = static_cast<double>(centres(f)) / static_cast<double>(full);
    EXPECT_GT(ratio, 0.75) << "a third of the strands, widened, covers " << ratio << " of all";
    EXPECT_LT(ratio, 1.25) << "a third of the strands, widened, covers " << ratio << " of all";
  }
  for (int a = 0; a < 3; ++a)
    for (std::uint32_t id : seen[a])
      for (int b = a + 1; b < 3; ++b) EXPECT_EQ(seen[b].count(id), 0u) << id;
  RenderOptions bad;
  bad.quality = Quality::Final;
  bad.finalSubset = 0;
  EXPECT_NE(errorOf([&] { r.render(s, bad); }).find("expected 1..16"), std::string::npos);
  bad.finalSubset = 17;
  EXPECT_NE(errorOf([&] { r.render(s, bad); }).find("expected 1..16"), std::string::npos);
}

}  // namespace
}  // namespace clhair::test
