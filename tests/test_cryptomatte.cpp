// test_cryptomatte.cpp — the Cryptomatte layers (--aov cryptomatte, clhair/cryptomatte.h).
//
// MurmurHash3_x86_32 against the published test vectors of Appleby's reference and the id
// conversion's exponent rule; the CLI's EXR read back with OpenImageIO: the channels and
// header the specification names, a manifest whose every entry is its name's id, and in a
// scene of two grooms side by side (overlapping in the middle) each groom's matte equal to
// the hair alpha within 1/255 wherever the other groom, rendered alone, covers nothing, and
// each strand's matte equal to it where the strand layer names one strand; through the
// library, with two grooms one over the other, the coverages of a pixel add up to the hair
// alpha and each groom's matte is its alpha "over" the other's, as rendered alone, and the
// beauty and the other layers are those of a frame without Cryptomatte.
// Tiny images and few strands: seconds each.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <glm/gtc/matrix_transform.hpp>

#include "clhair/aov.h"
#include "clhair/cryptomatte.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "exr_file.h"
#include "io/cyhair.h"
#include "test_util.h"

namespace clhair::test {
namespace {

using nlohmann::json;

// The matte of `name` in the file's layer `layer`: coverage summed over the ranks holding
// its id (what a compositor's Cryptomatte node computes).
std::vector<float> matte(const ExrFile& f, const std::string& layer, const std::string& name) {
  const float id = cryptomatteId(name);
  std::vector<float> m(static_cast<std::size_t>(f.width) * f.height, 0.0f);
  for (int set = 0; set < kCryptomatteRanks / 2; ++set) {
    const std::string prefix = layer + (set < 10 ? "0" : "") + std::to_string(set) + ".";
    for (const char* pair : {"RG", "BA"}) {
      const std::vector<float>& ids = f.channels.at(prefix + pair[0]);
      const std::vector<float>& cov = f.channels.at(prefix + pair[1]);
      for (std::size_t p = 0; p < m.size(); ++p)
        if (ids[p] == id) m[p] += cov[p];
    }
  }
  return m;
}

// Nine straight vertical strands 0.01 apart in x in the plane z = 0 (cyHair), 0.004 wide.
void writeVerticalStrands(const std::string& path) {
  CyHair h;
  for (int s = 0; s < 9; ++s) {
    h.segments.push_back(8);
    for (int k = 0; k < 9; ++k)
      h.points.insert(h.points.end(), {-0.04f + 0.01f * s, -0.05f + 0.0125f * k, 0.0f});
  }
  writeCyHair(h, path);
}

// Two instances of the vertical strands, "left" and "right" (0.02 nearer), 0.06 apart in x:
// the three innermost strands of each lie over one another in the middle of a 64x48 image.
std::string twoGroomScene(const std::string& dir, const std::string& only = "") {
  writeVerticalStrands(dir + "/vertical.hair");
  json grooms = json::array();
  for (const auto& [name, x] : {std::pair<std::string, double>{"left", -0.03},
                                std::pair<std::string, double>{"right", 0.03}}) {
    if (!only.empty() && only != name) continue;
    grooms.push_back({{"name", name},
                      {"strands_file", "vertical.hair"},
                      {"appearance", {{"strand_width", 0.004}}},
                      {"transform", {{"translate", {x, 0.0, x > 0.0 ? 0.02 : 0.0}}}}});
  }
  const json scene = {
      {"resolution", {64, 48}},
      {"camera", {{"position", {0.0, 0.0, 0.3}}, {"target", {0.0, 0.0, 0.0}}, {"fov", 35}}},
      {"lights", {{{"type", "directional"}, {"direction", {0.3, 1.0, 0.6}}}}},
      {"grooms", grooms}};
  const std::string path = dir + "/scene" + only + ".json";
  std::ofstream(path) << scene.dump(2);
  return path;
}

}  // namespace

TEST(Cryptomatte, MurmurHash3MatchesThePublishedVectors) {
  // MurmurHash3_x86_32 (Appleby's SMHasher reference), vectors as published with it and
  // with its ports
  struct Vector {
    std::string text;
    std::uint32_t seed, hash;
  } vectors[] = {{"", 0u, 0x00000000u},
                 {"", 1u, 0x514e28b7u},
                 {"", 0xffffffffu, 0x81f16f39u},
                 {"hello", 0u, 0x248bfa47u},
                 {"abc", 0u, 0xb3dd93fau},
                 {"aaaa", 0x9747b28cu, 0x5a97808au},
                 {"Hello, world!", 1234u, 0xfaf6cdb3u},
                 {"Hello, world!", 4321u, 0xbf505788u},
                 {"Hello, world!", 0x9747b28cu, 0x24884cbau},
                 {"The quick brown fox jumps over the lazy dog", 0u, 0x2e4ff723u},
                 {"The quick brown fox jumps over the lazy dog", 0x9747b28cu, 0x2fa826cdu}};
  for (const Vector& v : vectors)
    EXPECT_EQ(murmurHash3(v.text, v.seed), v.hash) << "\"" << v.text << "\" seed " << v.seed;
}

TEST(Cryptomatte, IdsAreFiniteNormalFloatsAndKeysSevenHexDigits) {
  // exponents 0 and 255 move to 1 and 254 (bit 23 flipped); every other hash is kept
  EXPECT_EQ(cryptomatteIdBits(0x00000000u), 0x00800000u);
  EXPECT_EQ(cryptomatteIdBits(0x807fffffu), 0x80ffffffu);
  EXPECT_EQ(cryptomatteIdBits(0x7f800001u), 0x7f000001u);
  EXPECT_EQ(cryptomatteIdBits(0xffffffffu), 0xff7fffffu);
  EXPECT_EQ(cryptomatteIdBits(0x248bfa47u), 0x248bfa47u);
  for (const char* name : {"hello", "left", "right", "left/3", "CryptoGroom"}) {
    const float id = cryptomatteId(name);
    EXPECT_TRUE(std::isnormal(id)) << name;
    std::uint32_t bits;
    std::memcpy(&bits, &id, 4);
    EXPECT_EQ(bits, cryptomatteIdBits(murmurHash3(name))) << name;
  }
  char hex[9];
  std::snprintf(hex, sizeof hex, "%08x", murmurHash3("CryptoGroom"));
  EXPECT_EQ(cryptomatteKey("CryptoGroom"), std::string(hex).substr(0, 7));
}

TEST(Cryptomatte, IsNamedAloneNeverByAll) {
  EXPECT_EQ(parseAovList("cryptomatte"), std::vector<Aov>{Aov::Cryptomatte});
  const std::vector<Aov> all = parseAovList("all");
  EXPECT_EQ(std::count(all.begin(), all.end(), Aov::Cryptomatte), 0);
  EXPECT_EQ(parseAovList("cryptomatte,all").size(), all.size() + 1);
}

TEST(Cryptomatte, EachGroomsMatteIsItsHairAlphaWhereTheGroomsDoNotOverlap) {
  const std::string dir = scratchDir();
  const CommandResult r = runCli("render " + quote(twoGroomScene(dir)) +
                                 " -q --aov cryptomatte,alpha,strand -o " + quote(dir + "/c.exr"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const ExrFile f = readExr(dir + "/c.exr");
  ASSERT_EQ(f.width, 64);
  // the channels: three RGBA sets per layer, 32-bit floats
  for (const char* layer : {"CryptoGroom", "CryptoStrand"})
    for (const char* set : {"00", "01", "02"})
      for (const char* c : {".R", ".G", ".B", ".A"}) {
        const std::string name = std::string(layer) + set + c;
        ASSERT_EQ(f.types.count(name), 1u) << name;
        EXPECT_EQ(f.types.at(name), OIIO::TypeDesc::FLOAT) << name;
      }
  // the header: name, hash, conversion and a manifest of every name to its id, per layer
  for (const char* layer : {"CryptoGroom", "CryptoStrand"}) {
    const std::string at = "cryptomatte/" + cryptomatteKey(layer) + "/";
    ASSERT_EQ(f.header.count(at + "name"), 1u) << layer;
    EXPECT_EQ(f.header.at(at + "name"), layer);
    EXPECT_EQ(f.header.at(at + "hash"), "MurmurHash3_32");
    EXPECT_EQ(f.header.at(at + "conversion"), "uint32_to_float32");
    const json manifest = json::parse(f.header.at(at + "manifest"));
    EXPECT_GE(manifest.size(), 2u) << layer;
    for (const auto& [name, hex] : manifest.items()) {
      char want[9];
      std::snprintf(want, sizeof want, "%08x", cryptomatteIdBits(murmurHash3(name)));
      EXPECT_EQ(hex.get<std::string>(), want) << name;
    }
  }
  const json groomManifest =
      json::parse(f.header.at("cryptomatte/" + cryptomatteKey("CryptoGroom") + "/manifest"));
  EXPECT_EQ(groomManifest.size(), 2u);
  EXPECT_EQ(groomManifest.count("left"), 1u);
  EXPECT_EQ(groomManifest.count("right"), 1u);
  // each groom alone gives the pixels the other covers
  std::map<std::string, std::vector<float>> alone;
  for (const char* g : {"left", "right"}) {
    const std::string out = dir + "/" + g + ".exr";
    const CommandResult a =
        runCli("render " + quote(twoGroomScene(dir, g)) + " -q --aov alpha -o " + quote(out));
    ASSERT_EQ(a.exitCode, 0) << a.output;
    alone[g] = readExr(out).channels.at("hair.A");
  }
  const std::vector<float>& alpha = f.channels.at("hair.A");
  const std::vector<float>& strandId = f.channels.at("strand.id");
  const std::vector<float>& strandGroom = f.channels.at("strand.groom");
  std::size_t overlap = 0;
  for (std::size_t p = 0; p < alpha.size(); ++p)
    overlap += alone["left"][p] > 0.0f && alone["right"][p] > 0.0f;
  EXPECT_GT(overlap, 10u) << "the scene should overlap the grooms somewhere";
  for (const auto& [g, other] : {std::pair<std::string, std::string>{"left", "right"},
                                 std::pair<std::string, std::string>{"right", "left"}}) {
    SCOPED_TRACE(g);
    const std::vector<float> m = matte(f, "CryptoGroom", g);
    std::size_t compared = 0, strands = 0;
    for (std::size_t p = 0; p < alpha.size(); ++p) {
      if (alone[other][p] > 0.0f) continue;
      EXPECT_NEAR(m[p], alone[g][p] > 0.0f ? alpha[p] : 0.0f, 1.0f / 255.0f) << "pixel " << p;
      compared += alpha[p] > 0.0f && alone[g][p] > 0.0f;
      // the strand the strand layer names there has the pixel's coverage
      if (alpha[p] > 0.0f && strandId[p] >= 0.0f && strandGroom[p] == (g == "left" ? 0 : 1)) {
        const std::string name = g + "/" + std::to_string(static_cast<int>(strandId[p]));
        const float id = cryptomatteId(name);
        float c = 0.0f;
        for (const char* set : {"00", "01", "02"}) {
          const std::string pre = std::string("CryptoStrand") + set + ".";
          if (f.channels.at(pre + "R")[p] == id) c += f.channels.at(pre + "G")[p];
          if (f.channels.at(pre + "B")[p] == id) c += f.channels.at(pre + "A")[p];
        }
        EXPECT_NEAR(c, alpha[p], 1.0f / 255.0f) << name << " at pixel " << p;
        ++strands;
      }
    }
    EXPECT_GT(compared, 40u);
    EXPECT_GT(strands, 20u);
  }
}

TEST(Cryptomatte, CoveragesAddUpToTheHairAlphaAndFollowTheCompositeOrder) {
  // two grooms, "back" and "front" 0.05 nearer and shifted half a strand spacing: groom 1
  // is composited over groom 0, so groom 0 keeps (1 - a1) of its alpha
  Scene s;
  s.width = 64;
  s.height = 48;
  s.camera.position = glm::vec3(0.0f, 0.0f, 0.3f);
  s.camera.target = glm::vec3(0.0f);
  s.camera.fovYDegrees = 35.0f;
  s.lights.push_back(Light{});
  StrandGroom g;
  g.name = "vertical";
  g.appearance.strandWidth = 0.004f;
  for (int i = 0; i < 9; ++i) {
    g.pointCounts.push_back(9);
    for (int k = 0; k < 9; ++k)
      g.points.emplace_back(-0.04f + 0.01f * i, -0.05f + 0.0125f * k, 0.0f);
  }
  auto groom = std::make_shared<const StrandGroom>(std::move(g));
  s.grooms.push_back(GroomInstance("back", groom));
  s.grooms.push_back(GroomInstance("front", groom));
  s.grooms[1].transform = glm::translate(glm::mat4(1.0f), glm::vec3(0.005f, 0.0f, 0.05f));
  Renderer r(sharedDevice());
  RenderOptions o;
  o.aovs = true;
  const Frame plain = r.render(s, o);
  o.cryptomatte = true;
  const Frame f = r.render(s, o);
  // the beauty and the layers are those of the frame without Cryptomatte
  EXPECT_EQ(f.color.rgba, plain.color.rgba);
  EXPECT_EQ(f.aovs.hairAlpha, plain.aovs.hairAlpha);
  EXPECT_EQ(f.aovs.z, plain.aovs.z);
  EXPECT_EQ(f.aovs.tangent, plain.aovs.tangent);
  ASSERT_EQ(f.cryptomatte.size(), 2u);
  const CryptomatteLayer& grooms = f.cryptomatte[0];
  EXPECT_EQ(grooms.name, "CryptoGroom");
  EXPECT_EQ(grooms.manifest.size(), 2u);
  Scene back = s, front = s;
  back.grooms.pop_back();
  front.grooms.erase(front.grooms.begin());
  o.cryptomatte = false;
  const std::vector<float> a0 = r.render(back, o).aovs.hairAlpha;
  const std::vector<float> a1 = r.render(front, o).aovs.hairAlpha;
  const std::vector<float> m0 = cryptomatteMatte(grooms, "back");
  const std::vector<float> m1 = cryptomatteMatte(grooms, "front");
  const std::size_t n = a0.size();
  std::size_t both = 0;
  for (std::size_t p = 0; p < n; ++p) {
    float sum = 0.0f;
    for (int k = 0; k < kCryptomatteRanks; ++k) {
      sum += grooms.coverage[k * n + p];
      if (k > 0) {
        EXPECT_LE(grooms.coverage[k * n + p], grooms.coverage[(k - 1) * n + p]);
      }
    }
    EXPECT_NEAR(sum, f.aovs.hairAlpha[p], 1e-5f) << "pixel " << p;
    EXPECT_NEAR(m1[p], a1[p], 1e-6f) << "pixel " << p;
    EXPECT_NEAR(m0[p], a0[p] * (1.0f - a1[p]), 1e-6f) << "pixel " << p;
    both += a0[p] > 0.1f && a1[p] > 0.1f;
    // strands: no more coverage than the hair has
    float strands = 0.0f;
    for (int k = 0; k < kCryptomatteRanks; ++k) strands += f.cryptomatte[1].coverage[k * n + p];
    EXPECT_LE(strands, f.aovs.hairAlpha[p] + 1e-5f) << "pixel " << p;
  }
  EXPECT_GT(both, 10u);
  // every strand name is "<groom>/<index>" of a strand the grooms have
  for (const auto& [name, bits] : f.cryptomatte[1].manifest) {
    const std::size_t slash = name.find('/');
    ASSERT_NE(slash, std::string::npos) << name;
    EXPECT_TRUE(name.substr(0, slash) == "back" || name.substr(0, slash) == "front") << name;
    EXPECT_LT(std::stoi(name.substr(slash + 1)), 9) << name;
  }
  EXPECT_GE(f.cryptomatte[1].manifest.size(), 9u);
}

TEST(Cryptomatte, CliRefusesMsaaAboveOneWithOneLine) {
  const std::string dir = scratchDir();
  const CommandResult r = runCli("render " + quote(twoGroomScene(dir)) +
                                 " --msaa 4 --aov cryptomatte -o " + quote(dir + "/c.exr"));
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(onlyErrorLine(r.output).find("--aov cryptomatte needs --msaa 1"), std::string::npos)
      << r.output;
  EXPECT_FALSE(std::ifstream(dir + "/c.exr").good());
}

}  // namespace clhair::test
