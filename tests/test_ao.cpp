// test_ao.cpp — ambient occlusion baked per hair-mesh vertex on the device
// (kernels/ao.cl): values in [0, 1], roots under the hair darker than the tips, the
// inside of a bundle stack darker than its outside, and the bake is deterministic.
#include <algorithm>
#include <numeric>

#include "clhair/renderer.h"
#include "groom/presets.h"
#include "test_util.h"

namespace clhair {
namespace {

TEST(AmbientOcclusion, RootsAreDarkerThanTips) {
  HairMesh m = makeGroomPreset("long_wavy");
  Renderer r(test::sharedDevice());
  std::vector<float> ao = r.bakeAmbientOcclusion(m);
  ASSERT_EQ(ao.size(), static_cast<std::size_t>(m.layerCount) * m.vertexCount);
  for (float a : ao) {
    ASSERT_GE(a, 0.0f);
    ASSERT_LE(a, 1.0f);
  }
  auto layerMean = [&](int l) {
    double s = 0;
    for (int v = 0; v < m.vertexCount; ++v) s += ao[static_cast<std::size_t>(l) * m.vertexCount + v];
    return s / m.vertexCount;
  };
  const double roots = layerMean(0), middle = layerMean(m.layerCount / 2), tips = layerMean(m.layerCount - 1);
  RecordProperty("ao_roots", std::to_string(roots));
  RecordProperty("ao_middle", std::to_string(middle));
  RecordProperty("ao_tips", std::to_string(tips));
  EXPECT_LT(roots, 0.5 * tips) << "roots sit under all the hair and against the scalp";
  EXPECT_LT(roots, middle);
  // deterministic: a second bake is bit-identical
  EXPECT_TRUE(ao == r.bakeAmbientOcclusion(m));
}

TEST(AmbientOcclusion, DenserHairOccludesMore) {
  HairMesh sparse = makeGroomPreset("fur_sphere");
  sparse.strandCount = 2000;
  HairMesh dense = sparse;
  dense.strandCount = 200000;
  Renderer r(test::sharedDevice());
  std::vector<float> a = r.bakeAmbientOcclusion(sparse), b = r.bakeAmbientOcclusion(dense);
  // the middle layer of the fur sits inside the coat
  auto mid = [&](const std::vector<float>& v) {
    double s = 0;
    for (int i = 0; i < sparse.vertexCount; ++i) s += v[static_cast<std::size_t>(sparse.vertexCount) + i];
    return s / sparse.vertexCount;
  };
  RecordProperty("ao_mid_sparse", std::to_string(mid(a)));
  RecordProperty("ao_mid_dense", std::to_string(mid(b)));
  EXPECT_LT(mid(b), mid(a) - 0.05);
}

}  // namespace
}  // namespace clhair
