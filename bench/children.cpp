// children.cpp — the benchmark's children section (clhair_bench --only children):
// Children from guides (docs/scene-format.md, "Children"): 3000 guides of groom1 with
// 16 follow hairs each against the same strands read as a strand file: the strand pass
// at each distance, LOD off and on.
#include "harness.h"

#include <cstdio>
#include <memory>
#include <string>

#include "io/cyhair.h"
#include "io/tressfx.h"

namespace clhair::bench {

void runChildren(Run& r) {
  // Children from guides (docs/scene-format.md, "Children"): 3000 guides of groom1, as a
  // guides-only TressFX export would hold them (32 points each), with 16 follow hairs
  // each, against the same 51 000 strands exported and read as a strand file. The strand
  // pass (device time, median) at each distance, LOD off and on.
  HairMesh guidesMesh = *r.scenes[0].grooms[0].mesh;
  guidesMesh.strandCount = 3000;
  StrandSet gs = r.b.renderer.generateStrands(guidesMesh);
  CyHair gh;
  for (std::uint32_t c : gs.pointCounts) gh.segments.push_back(c - 1);
  gh.points = gs.points;
  const CyHair resampled = resampleStrands(gh, 32);
  StrandGroom guides;
  guides.name = "groom1 guides";
  std::size_t at = 0;
  for (std::uint32_t seg : resampled.segments) {
    guides.pointCounts.push_back(seg + 1);
    for (std::uint32_t k = 0; k <= seg; ++k, ++at)
      guides.points.emplace_back(resampled.points[3 * at], resampled.points[3 * at + 1],
                                 resampled.points[3 * at + 2]);
  }
  guides.appearance = guidesMesh.appearance;
  guides.lod = guidesMesh.lod;
  guides.children.count = 16;
  guides.children.radius = kTressFxFollowRadiusMetres;
  guides.children.tipSpread = kTressFxTipSeparation;
  StrandSet all = r.b.renderer.generateStrands(guides);
  StrandGroom file;
  file.name = "groom1 children as a file";
  file.pointCounts = all.pointCounts;
  for (std::size_t i = 0; i < all.points.size(); i += 3)
    file.points.emplace_back(all.points[i], all.points[i + 1], all.points[i + 2]);
  file.appearance = guides.appearance;
  file.lod = guides.lod;
  auto kids = std::make_shared<const StrandGroom>(std::move(guides));
  auto stored = std::make_shared<const StrandGroom>(std::move(file));
  r.md << "\n## Children from guides (3000 guides x 17 = " << stored->pointCounts.size()
       << " strands, " << r.opt.width << "x" << r.opt.height
       << ")\n\n| distance | LOD | children ms | file ms | ratio |\n|---|---|---|---|---|\n";
  const CameraPreset dists[3] = {CameraPreset::Close, CameraPreset::Mid, CameraPreset::Far};
  const char* distNames[3] = {"close", "mid", "far"};
  for (int lod = 0; lod < 2; ++lod)
    for (int d = 0; d < 3; ++d) {
      RenderOptions o;
      o.lod = lod ? Toggle::On : Toggle::Off;
      Scene s = r.scenes[0];
      s.grooms[0] = GroomInstance("children", stored, s.grooms[0].transform);
      s = framed(s, dists[d], r.opt.width, r.opt.height);  // one camera for both
      Scene k = s;
      k.grooms[0].strands = kids;
      const double tk = stageMedian(r.b.measure(k, o, false), "strands");
      const double tf = stageMedian(r.b.measure(s, o, false), "strands");
      r.md << "| " << distNames[d] << " | " << (lod ? "on" : "off") << " | " << fmt(tk) << " | "
           << fmt(tf) << " | " << fmt(tk / tf) << " |\n";
      r.report["children"][std::string(distNames[d]) + (lod ? "_lod" : "")] = {
          {"children_ms", tk}, {"file_ms", tf}, {"ratio", tk / tf}};
      std::fprintf(stderr, "children %s LOD %s: strands %.1f ms, file %.1f ms, %.3fx\n",
                   distNames[d], lod ? "on" : "off", tk, tf, tk / tf);
    }
}

}  // namespace clhair::bench
