// test_fit.cpp — fitting a hair mesh to strands (clhair/fit.h, docs/fitting.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <cstdio>
#include <cstdlib>

#include "clhair/error.h"
#include "clhair/fit.h"
#include "fit_groom.h"
#include "test_util.h"

namespace clhair {
namespace {

TEST(FitSynthetic, Explore) {
  HairMesh m = test::patchMesh(8, 5, 0.1f, 0.1f);
  m.style.curlAmplitude = 0.003f;
  m.style.curlFrequency = 4.0f;
  m.style.curlHelix = std::getenv("CLHAIR_HELIX") ? std::atof(std::getenv("CLHAIR_HELIX")) : 0.6f;
  m.style.curlPhaseJitter = std::getenv("CLHAIR_J") ? std::atof(std::getenv("CLHAIR_J")) : 1.0f;
  m.style.clumpStrength = 0.5f;
  m.style.clumpFrequency = std::getenv("CLHAIR_CF") ? std::atof(std::getenv("CLHAIR_CF")) : 40.0f;
  m.style.clumpShape = 1.5f;
  m.style.frizzAmplitude = 0.001f;
  m.style.frizzFrequency = 6.0f;
  m.style.flyawayFraction = 0.05f;
  m.style.flyawayAmplitude = 0.004f;
  m.style.lengthVariation = 0.2f;
  const std::string on = std::getenv("CLHAIR_SYN") ? std::getenv("CLHAIR_SYN") : "curl,clump,frizz,fly,len";
  if (on.find("curl") == std::string::npos) m.style.curlAmplitude = 0;
  if (on.find("clump") == std::string::npos) m.style.clumpStrength = 0;
  if (on.find("frizz") == std::string::npos) m.style.frizzAmplitude = 0;
  if (on.find("fly") == std::string::npos) m.style.flyawayFraction = 0;
  if (on.find("len") == std::string::npos) m.style.lengthVariation = 0;
  const StrandGroom s = test::strandsOf(m);
  FitOptions o;
  o.bundles = 64;
  o.layers = 5;
  o.errorSample = 2000;
  const FitResult r = fitHairMesh(s, o);
  {
    std::vector<float> lens;
    for (const auto& f : r.mesh.faces) {
      float len = 0;
      glm::vec3 prev(0);
      for (int l = 0; l < r.mesh.layerCount; ++l) {
        glm::vec3 c(0);
        for (int k = 0; k < 4; ++k) c += 0.25f * r.mesh.position(l, f[k]);
        if (l > 0) len += glm::length(c - prev);
        prev = c;
      }
      lens.push_back(len);
    }
    std::sort(lens.begin(), lens.end());
    std::printf("cage centre lengths: min %g median %g max %g\n", lens.front(), lens[lens.size() / 2], lens.back());
  }
  const std::string j = fitReportJson(r.report);
  std::printf("%s\n", (j.substr(0, 300) + j.substr(j.find("\"style\""), 600) + j.substr(j.rfind("\"vertices\""), 30)).c_str());
}

}  // namespace
}  // namespace clhair
