// explicit.cpp — the benchmark's explicit section (clhair_bench --only explicit):
// The hair mesh vs the same strands as a cyHair file: device bytes, frame times.
#include "harness.h"

#include <cstdio>
#include <memory>

namespace clhair::bench {

void runExplicit(Run& r) {
  const int width = r.opt.width;
  const int height = r.opt.height;
  Bench& b = r.b;
  std::ostringstream& md = r.md;
  json& report = r.report;
  const auto& scenes = r.scenes;
  const auto& groomNames = r.groomNames;
  auto exportedGroom1 = [&r] { return r.exportedGroom1(); };
  // Bhokare §4: the groom as a hair mesh vs the same strands exported to cyHair and read
  // back as an explicit strand groom: device bytes and frame time of each
  std::shared_ptr<const StrandGroom> strands = exportedGroom1();
  md << "\n## Hair mesh vs explicit strands (" << groomNames[0] << ", " << width << "x" << height
     << ")\n\n| representation | device bytes | close, LOD off ms | far, LOD on ms "
        "|\n|---|---|---|---|\n";
  for (int explicitStrands = 0; explicitStrands < 2; ++explicitStrands) {
    Scene s = scenes[0];
    if (explicitStrands)
      s.grooms[0] = GroomInstance(s.grooms[0].name, strands, s.grooms[0].transform);
    std::uint64_t bytes = b.renderer.groomDeviceBytes(s.grooms[0]);
    RenderOptions o;
    o.lod = 0;
    Measured close = b.measure(framed(s, CameraPreset::Close, width, height), o, false);
    o.lod = 1;
    Measured far = b.measure(framed(s, CameraPreset::Far, width, height), o, false);
    const char* name = explicitStrands ? "cyHair strands" : "hair mesh";
    md << "| " << name << " | " << bytes << " | " << fmt(close.total.median) << " | "
       << fmt(far.total.median) << " |\n";
    report["explicit"][name] = {{"device_bytes", bytes},
                                {"close_ms", close.total.median},
                                {"far_lod_ms", far.total.median}};
    std::fprintf(stderr, "explicit %s: %llu bytes, close %.1f ms, far %.1f ms\n", name,
                 static_cast<unsigned long long>(bytes), close.total.median, far.total.median);
  }
}

}  // namespace clhair::bench
