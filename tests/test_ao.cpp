// test_ao.cpp — ambient occlusion baked per hair-mesh vertex on the device
// (kernels/ao.cl): values in [0, 1], roots under the hair darker than the tips, denser hair
// darker, the bake deterministic, and, on a slab of straight dense hair, a vertex deep
// inside black while vertices on its side and corner keep the share of directions that
// leave the groom without entering it. The bake is kept in the device's cache folder, one
// entry per groom.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numeric>

#include <glm/vec3.hpp>

#include "cl/binary_cache.h"
#include "clhair/renderer.h"
#include "groom/groom_data.h"
#include "groom/presets.h"
#include "test_util.h"

namespace clhair {
namespace {

TEST(AmbientOcclusion, RootsAreDarkerThanTips) {
  HairMesh m = makeGroomPreset("long_wavy");
  Renderer r(test::openWithCache("off", false));  // every bake computed, none read back
  std::vector<float> ao = r.bakeAmbientOcclusion(m);
  ASSERT_EQ(ao.size(), static_cast<std::size_t>(m.layerCount) * m.vertexCount);
  for (float a : ao) {
    ASSERT_GE(a, 0.0f);
    ASSERT_LE(a, 1.0f);
  }
  auto layerMean = [&](int l) {
    double s = 0;
    for (int v = 0; v < m.vertexCount; ++v)
      s += ao[static_cast<std::size_t>(l) * m.vertexCount + v];
    return s / m.vertexCount;
  };
  const double roots = layerMean(0), middle = layerMean(m.layerCount / 2),
               tips = layerMean(m.layerCount - 1);
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
    for (int i = 0; i < sparse.vertexCount; ++i)
      s += v[static_cast<std::size_t>(sparse.vertexCount) + i];
    return s / sparse.vertexCount;
  };
  RecordProperty("ao_mid_sparse", std::to_string(mid(a)));
  RecordProperty("ao_mid_dense", std::to_string(mid(b)));
  EXPECT_LT(mid(b), mid(a) - 0.05);
}

// A slab of straight hair: a 6 x 6 grid of 1 cm scalp quads in the plane y = 0 (vertex (i, j)
// at x = i - 3 cm, z = j - 3 cm), extruded straight up through 5 layers 0.5 cm apart, no
// styling, so the strands fill the box [-3, 3] x [0, 2] x [-3, 3] cm and nothing outside it.
// (Low enough that the bake's 33-point strands have segments shorter than its ~1 mm voxels:
// ao_voxelize puts a segment's length in the voxel of its midpoint.)
HairMesh hairSlab(std::int64_t strands) {
  HairMesh m;
  m.name = "slab";
  const int n = 7;  // vertices per side
  m.layerCount = 5;
  m.vertexCount = n * n;
  auto vi = [&](int i, int j) { return j * n + i; };
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i)
      m.faces.push_back({vi(i, j), vi(i, j + 1), vi(i + 1, j + 1), vi(i + 1, j)});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) m.uv.push_back(glm::vec2(i / 6.0f, j / 6.0f));
  m.positions.resize(static_cast<std::size_t>(m.layerCount) * m.vertexCount);
  for (int l = 0; l < m.layerCount; ++l)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        m.positions[static_cast<std::size_t>(l) * m.vertexCount + vi(i, j)] =
            glm::vec3(0.01f * (i - 3), 0.005f * l, 0.01f * (j - 3));
  m.strandCount = strands;
  m.controlPoints = 17;
  return m;
}

// ao.cl's direction k of 64 on the spherical Fibonacci set (its "z" is the y axis).
glm::dvec3 fibonacciDirection(int k) {
  const int dirs = 64;
  const double y = 1.0 - (2.0 * k + 1.0) / dirs, r = std::sqrt(std::max(0.0, 1.0 - y * y));
  const double phi = k * 2.39996322972865332;
  return {r * std::cos(phi), y, r * std::sin(phi)};
}

// The bake of ao_bake for one vertex of the slab, on the CPU, with the density the strands
// deposit on average: sigma in the slab box, each voxel of the bake's grid (the groom's
// bounds, 64 voxels across the longest side, renderer.cpp bakeAo) holding sigma times the
// share of it inside the box. Same directions, same march (from one voxel out, half-voxel
// steps, leaving once outside the grid beyond two voxels), the scalp square blocks.
double cpuSlabAo(const HairMesh& slab, const glm::dvec3& p, double sigma) {
  const GroomData d = prepareGroom(slab);
  const glm::dvec3 lo(d.boundsMin), hi(d.boundsMax);
  const double voxel = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) / 64.0 * 1.02;
  const glm::ivec3 dims(static_cast<int>(std::ceil((hi.x - lo.x) / voxel)) + 1,
                        static_cast<int>(std::ceil((hi.y - lo.y) / voxel)) + 1,
                        static_cast<int>(std::ceil((hi.z - lo.z) / voxel)) + 1);
  const glm::dvec3 boxLo(-0.03, 0.0, -0.03), boxHi(0.03, 0.02, 0.03);
  auto overlap = [&](int axis, int i) {
    const double a = lo[axis] + i * voxel, b = a + voxel;
    return std::max(0.0, std::min(b, boxHi[axis]) - std::max(a, boxLo[axis])) / voxel;
  };
  const double extent = voxel * std::max({dims.x, dims.y, dims.z});
  double visible = 0.0;
  for (int k = 0; k < 64; ++k) {
    const glm::dvec3 dir = fibonacciDirection(k);
    if (dir.y < 0.0) {  // the scalp square at y = 0
      const double t = -p.y / dir.y;
      const glm::dvec3 q = p + t * dir;
      if (std::fabs(q.x) <= 0.03 && std::fabs(q.z) <= 0.03) continue;
    }
    double tau = 0.0;
    for (double t = voxel; t < extent; t += 0.5 * voxel) {
      const glm::dvec3 c = (p + t * dir - lo) / voxel;
      const glm::ivec3 v(static_cast<int>(std::floor(c.x)), static_cast<int>(std::floor(c.y)),
                         static_cast<int>(std::floor(c.z)));
      if (v.x < 0 || v.y < 0 || v.z < 0 || v.x >= dims.x || v.y >= dims.y || v.z >= dims.z) {
        if (t > 2.0 * voxel) break;
        continue;
      }
      tau += sigma * overlap(0, v.x) * overlap(1, v.y) * overlap(2, v.z) * 0.5 * voxel;
    }
    visible += std::exp(-tau);
  }
  return visible / 64.0;
}

TEST(AmbientOcclusion, InsideOfTheGroomIsDarkerThanItsOutside) {
  // 2000 strands of 70 um per 1 cm^2 bundle: extinction sigma_t = length per volume x
  // diameter = 2000 x 7e-5 m / 1e-4 m^2 = 1400 / m (ao.cl), an optical depth of 14 per cm:
  // every ray that runs through 0.5 cm of this hair keeps under 1e-3. So at the inner layers
  // (0.5 to 1.5 cm up) a vertex in the centre column is black (every direction crosses 0.5
  // cm of hair or more, or meets the scalp), one in the middle of a side keeps about the
  // half of the directions that point away from the slab, a corner the three quarters that
  // point away from either of its faces (less what the voxels the faces cut take from
  // grazing directions). The device must match the CPU bake of the average density within
  // 0.04: the bake samples 20000 of the 72000 strands, about 9 segments per voxel, whose
  // scatter changes a grazing ray's optical depth by some 10 %.
  const double sigma = 2000.0 * 7e-5 / 1e-4;
  HairMesh slab = hairSlab(36 * 2000);
  ASSERT_EQ(slab.appearance.strandWidth, 7e-5f);
  ASSERT_NO_THROW(validateHairMesh(slab, "slab"));
  Renderer r(test::sharedDevice());
  const std::vector<float> ao = r.bakeAmbientOcclusion(slab);
  ASSERT_EQ(ao.size(), static_cast<std::size_t>(slab.layerCount) * slab.vertexCount);
  auto at = [&](int layer, int i, int j) {
    return ao[static_cast<std::size_t>(layer) * slab.vertexCount + j * 7 + i];
  };
  RecordProperty("ao_centre", std::to_string(at(2, 3, 3)));
  RecordProperty("ao_side", std::to_string(at(2, 0, 3)));
  RecordProperty("ao_corner", std::to_string(at(2, 0, 0)));
  for (int layer : {1, 2, 3}) {
    EXPECT_LT(at(layer, 3, 3), 0.01) << "inside the slab, layer " << layer;
    for (auto [i, j] :
         {std::pair{3, 3}, {0, 3}, {6, 3}, {3, 0}, {3, 6}, {0, 0}, {6, 0}, {0, 6}, {6, 6}}) {
      const glm::dvec3 p(0.01 * (i - 3), 0.005 * layer, 0.01 * (j - 3));
      const double want = cpuSlabAo(slab, p, sigma);
      const bool corner = (i == 0 || i == 6) && (j == 0 || j == 6), centre = i == 3 && j == 3;
      if (!centre) {
        EXPECT_GT(want, corner ? 0.5 : 0.3) << "the CPU bake: (" << i << ", " << j << ")";
      }
      EXPECT_NEAR(at(layer, i, j), want, 0.04)
          << "vertex (" << i << ", " << j << "), layer " << layer;
    }
  }
}

std::vector<std::filesystem::path> aoEntries(const std::string& dir) {
  std::vector<std::filesystem::path> out;
  std::error_code ec;
  const std::filesystem::path folder =
      std::filesystem::path(BinaryCache(dir).entryPath("x")).parent_path();
  for (const auto& e : std::filesystem::directory_iterator(folder, ec))
    if (e.path().extension() == ".ao") out.push_back(e.path());
  return out;
}

// An entry holding `v` as the cache writes it (binary_cache.h: its key is its file name).
void writeFloats(const std::filesystem::path& p, const std::vector<float>& v) {
  std::vector<unsigned char> bytes(v.size() * sizeof(float));
  std::memcpy(bytes.data(), v.data(), bytes.size());
  const std::string entry = encodeCacheEntry(p.filename().string(), bytes);
  std::ofstream(p, std::ios::binary | std::ios::trunc)
      .write(entry.data(), static_cast<std::streamsize>(entry.size()));
}

std::vector<float> entryFloats(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto bytes = decodeCacheEntry(text, p.filename().string());
  std::vector<float> v(bytes ? bytes->size() / sizeof(float) : 0);
  if (bytes) std::memcpy(v.data(), bytes->data(), v.size() * sizeof(float));
  return v;
}

// The ambient-occlusion bake of a hair mesh is kept in the same folder: one entry per
// groom, read back instead of baking (shown by planting an entry the bake would never
// make), a damaged entry baked again, and another groom never served a stored bake.
TEST(AmbientOcclusion, BakeIsKeptInTheCacheFolderPerGroom) {
  const std::string dir = test::scratchDir() + "/ao-cache";
  Renderer r(test::openWithCache(dir, false));  // the bakes' entries, not the programs'
  HairMesh m = hairSlab(2000);
  const std::vector<float> baked = r.bakeAmbientOcclusion(m);
  ASSERT_FALSE(baked.empty());
  const std::vector<std::filesystem::path> stored = aoEntries(dir);
  ASSERT_EQ(stored.size(), 1u) << "one bake, one entry";
  EXPECT_EQ(entryFloats(stored[0]), baked) << "the entry holds the bake";
  EXPECT_EQ(r.bakeAmbientOcclusion(m), baked);

  // an entry the bake cannot have made (every vertex 0.25) is what the next bake returns
  const std::vector<float> planted(baked.size(), 0.25f);
  writeFloats(stored[0], planted);
  EXPECT_EQ(r.bakeAmbientOcclusion(m), planted) << "the stored bake is read, not recomputed";

  // damaged entries (a value outside [0, 1], a short file) are baked again and rewritten
  std::vector<float> bad = baked;
  bad[bad.size() / 2] = 2.0f;
  writeFloats(stored[0], bad);
  EXPECT_EQ(r.bakeAmbientOcclusion(m), baked);
  writeFloats(stored[0], std::vector<float>(3, 0.5f));
  EXPECT_EQ(r.bakeAmbientOcclusion(m), baked);
  std::filesystem::resize_file(stored[0], std::filesystem::file_size(stored[0]) / 2);
  EXPECT_EQ(r.bakeAmbientOcclusion(m), baked) << "an entry cut short is baked again";
  EXPECT_EQ(entryFloats(stored[0]), baked) << "and rewritten whole";
  writeFloats(stored[0], planted);

  // a different groom (more strands) has its own entry, never the planted one
  HairMesh denser = hairSlab(4000);
  const std::vector<float> other = r.bakeAmbientOcclusion(denser);
  EXPECT_NE(other, planted);
  EXPECT_EQ(aoEntries(dir).size(), 2u);
}

}  // namespace
}  // namespace clhair
