// cryptomatte_pass.cpp — the Cryptomatte layers (passes.h, clhair/cryptomatte.h): after each
// groom's composite, its hair alpha and strand identities are folded into the ranked lists
// of both layers on the device (kernels/cryptomatte.cl); the frame's first groom drawn
// creates the lists, its last reads them back without blocking, and a finisher names the
// keys (grooms by their name in the scene, strands as "<groom>/<index>") and hashes them.
#include <memory>

#include "io/cryptomatte_io.h"
#include "passes/passes.h"
#include "stages/cryptomatte_stage.h"

namespace clhair {

namespace {

// The ranked lists of both layers on the device, on the graph's blackboard once the first
// groom's pass has created them.
struct CryptoHandles {
  FrameGraph::Handle groomKeys, groomCoverage, strandKeys, strandCoverage;
};
constexpr const char* kCryptoLists = "cryptomatte lists";

// The lists on the host until the frame completes.
struct CryptoHost {
  std::size_t pixels = 0;
  std::vector<std::uint64_t> groomKeys, strandKeys;
  std::vector<float> groomCoverage, strandCoverage;
};

// Each groom's name; a groom's key is the first groom with its name (instances of one name
// share their ids, as the specification's names do).
std::vector<std::string> groomNames(const FramePlan& plan) {
  std::vector<std::string> names;
  for (const GroomPlan& g : plan.grooms) {
    const std::string& n = g.draw.instance->name;
    names.push_back(n.empty() ? "groom " + std::to_string(g.index) : n);
  }
  return names;
}

std::uint32_t groomKey(const std::vector<std::string>& names, std::size_t k) {
  std::size_t j = 0;
  while (names[j] != names[k]) ++j;
  return static_cast<std::uint32_t>(j);
}

// Reads the lists into `host` and names them in `out`'s frame once it completes.
void readBack(const FrameGraph::Resources& res, const CryptoHandles& h, Renderer::Impl& r,
              FramePlan& plan, PendingFrame& out) {
  auto host = std::make_shared<CryptoHost>();
  const std::size_t n = plan.pixels, ranks = kCryptomatteRanks;
  host->pixels = n;
  host->groomKeys.resize(n * ranks);
  host->strandKeys.resize(n * ranks);
  host->groomCoverage.resize(n * ranks);
  host->strandCoverage.resize(n * ranks);
  out.read(r.dev, r.pinned, res[h.groomKeys], 0, host->groomKeys.data(), n * ranks * 8);
  out.read(r.dev, r.pinned, res[h.groomCoverage], 0, host->groomCoverage.data(), n * ranks * 4);
  out.read(r.dev, r.pinned, res[h.strandKeys], 0, host->strandKeys.data(), n * ranks * 8);
  out.read(r.dev, r.pinned, res[h.strandCoverage], 0, host->strandCoverage.data(), n * ranks * 4);
  out.finishers.push_back([host, names = groomNames(plan)](PendingFrame& p) {
    const auto groom = [&](std::uint64_t key) { return names.at(key); };
    const auto strand = [&](std::uint64_t key) {
      return names.at(key >> 32) + "/" + std::to_string(key & 0xffffffffu);
    };
    std::vector<CryptomatteLayer>& layers = p.frames[0].cryptomatte;
    layers.clear();
    layers.push_back(cryptomatteLayer(kCryptoGroomLayer, host->pixels, host->groomKeys,
                                      host->groomCoverage, groom));
    layers.push_back(cryptomatteLayer(kCryptoStrandLayer, host->pixels, host->strandKeys,
                                      host->strandCoverage, strand));
  });
}

}  // namespace

void addCryptomattePass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp,
                        PendingFrame& out) {
  const CryptoHandles* made = g.blackboard().get<CryptoHandles>(kCryptoLists);
  const bool first = made == nullptr;
  CryptoHandles h = first ? CryptoHandles{} : *made;
  if (first) {
    h.groomKeys = g.create("cryptomatte groom keys", CryptomatteStage::keyBytes(plan.pixels));
    h.groomCoverage =
        g.create("cryptomatte groom coverage", CryptomatteStage::coverageBytes(plan.pixels));
    h.strandKeys = g.create("cryptomatte strand keys", CryptomatteStage::keyBytes(plan.pixels));
    h.strandCoverage =
        g.create("cryptomatte strand coverage", CryptomatteStage::coverageBytes(plan.pixels));
    g.blackboard().put(kCryptoLists, h);
  }
  const bool last = gp.index == plan.lastDrawn;
  struct Data {
    FrameGraph::Handle result, gbuffer;
  };
  g.addPass<Data>(
      "cryptomatte " + std::to_string(gp.index),
      [&, first, last](FrameGraph::Setup& s, Data& d) {
        d.result = s.read(gp.views[0].result);
        d.gbuffer = s.read(plan.camera().gbuffer);
        s.kernel("cryptomatte_groom");
        for (FrameGraph::Handle list :
             {h.groomKeys, h.groomCoverage, h.strandKeys, h.strandCoverage})
          first ? s.write(list) : s.readWrite(list);
        if (last) s.sideEffect();  // the read-back
      },
      [&, h, first, last](const Data& d, const FrameGraph::Resources& res) {
        const std::vector<std::string> names = groomNames(plan);
        CryptomatteStage::Params p;
        p.width = static_cast<std::uint32_t>(plan.scene.width);
        p.height = static_cast<std::uint32_t>(plan.scene.height);
        p.first = first;
        p.groomKey = groomKey(names, gp.index);
        p.result = &res[d.result];
        p.gbuffer = &res[d.gbuffer];
        p.layers = static_cast<std::size_t>(plan.camera().target->usedLayers());
        p.groomKeys = &res[h.groomKeys];
        p.groomCoverage = &res[h.groomCoverage];
        p.strandKeys = &res[h.strandKeys];
        p.strandCoverage = &res[h.strandCoverage];
        r.stage<CryptomatteStage>().enqueue(p, &r.profiler);
        if (last) readBack(res, h, r, plan, out);
      });
}

}  // namespace clhair
