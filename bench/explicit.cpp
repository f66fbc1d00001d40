// explicit.cpp — the benchmark's explicit section (clhair_bench --only explicit):
// The hair mesh vs the same strands as a cyHair file: device bytes, frame times.
#include "harness.h"

#include <cstdio>
#include <memory>

namespace clhair::bench {

void runExplicit(Run& r) {
  auto exportedGroom1 = [&r] { return r.exportedGroom1(); };
  // Bhokare §4: the groom as a hair mesh vs the same strands exported to cyHair and read
  // back as an explicit strand groom: device bytes and frame time of each
  std::shared_ptr<const StrandGroom> strands = exportedGroom1();
  r.md << "\n## Hair mesh vs explicit strands (" << r.groomNames[0] << ", " << r.opt.width << "x"
       << r.opt.height
       << ")\n\n| representation | device bytes | close, LOD off ms | far, LOD on ms "
          "|\n|---|---|---|---|\n";
  for (int explicitStrands = 0; explicitStrands < 2; ++explicitStrands) {
    Scene s = r.scenes[0];
    if (explicitStrands)
      s.grooms[0] = GroomInstance(s.grooms[0].name, strands, s.grooms[0].transform);
    std::uint64_t bytes = r.b.renderer.groomDeviceBytes(s.grooms[0]);
    RenderOptions o;
    o.lod = Toggle::Off;
    Measured close =
        r.b.measure(framed(s, CameraPreset::Close, r.opt.width, r.opt.height), o, false);
    o.lod = Toggle::On;
    Measured far = r.b.measure(framed(s, CameraPreset::Far, r.opt.width, r.opt.height), o, false);
    const char* name = explicitStrands ? "cyHair strands" : "hair mesh";
    r.md << "| " << name << " | " << bytes << " | " << fmt(close.total.median) << " | "
         << fmt(far.total.median) << " |\n";
    r.report["explicit"][name] = {{"device_bytes", bytes},
                                  {"close_ms", close.total.median},
                                  {"far_lod_ms", far.total.median}};
    std::fprintf(stderr, "explicit %s: %llu bytes, close %.1f ms, far %.1f ms\n", name,
                 static_cast<unsigned long long>(bytes), close.total.median, far.total.median);
  }
}

}  // namespace clhair::bench
