// path_convergence.cpp — the benchmark's pathref section (clhair_bench --only pathref): time
// and error of the path-traced reference (`--reference path`) against its sample count.
// The default scene (assets/scenes/default.json) at 320x180 is path traced with 16, 64 and
// 256 samples per pixel (--quick: 4 and 16) and compared with a 1024-sample image (--quick:
// 64) of another seed: RMSE of the linear colour over the image, the mean colour over the
// head (pixels where a camera ray of the reference met hair or the head sphere) and its
// largest channel error relative to the reference's, seconds and rays per second of the
// trace.
// Host CPU work (Embree): the times depend on the host's cores and load, not on the device.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "harness.h"

namespace clhair::bench {

namespace {

struct PathRun {
  Frame frame;
  double seconds = 0.0;
};

PathRun trace(Renderer& renderer, const Scene& s, int spp, std::uint32_t seed) {
  ReferenceOptions ro;
  ro.method = ReferenceMethod::Path;
  ro.spp = spp;
  ro.pathSeed = seed;
  const auto t0 = std::chrono::steady_clock::now();
  PathRun out;
  out.frame = renderer.renderReference(s, ro);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace

void runPathConvergence(Run& r) {
  Scene s = loadScene(std::string(CLHAIR_SOURCE_DIR) + "/assets/scenes/default.json");
  s.width = 320;
  s.height = 180;
  const std::vector<int> spps =
      r.opt.quick ? std::vector<int>{4, 16} : std::vector<int>{16, 64, 256};
  const int refSpp = r.opt.quick ? 64 : 1024;
  std::fprintf(stderr, "pathref: %d-sample reference at %dx%d\n", refSpp, s.width, s.height);
  const PathRun ref = trace(r.b.renderer, s, refSpp, 1000u);
  const std::size_t P = ref.frame.depth.size();
  auto hairMean = [&](const Frame& f) {
    double m[3] = {0.0, 0.0, 0.0};
    std::size_t n = 0;
    for (std::size_t i = 0; i < P; ++i)
      if (std::isfinite(ref.frame.depth[i])) {
        ++n;
        for (int c = 0; c < 3; ++c) m[c] += f.color.rgba[4 * i + c];
      }
    for (double& v : m) v /= static_cast<double>(std::max<std::size_t>(n, 1));
    return std::vector<double>{m[0], m[1], m[2]};
  };
  const std::vector<double> refMean = hairMean(ref.frame);
  auto raysPerSecond = [](const Frame& f) {
    const double ms = f.stageMs("paths");
    return ms > 0.0 ? 1e3 * static_cast<double>(f.stats.pathRays) / ms : 0.0;
  };
  r.md << "\n## Path reference: time and error against samples per pixel (default scene, "
       << s.width << "x" << s.height << ", reference " << refSpp
       << " samples)\n\n| spp | seconds | M rays/s | RMSE (linear) | mean colour over the "
          "head | largest channel error of that mean |\n|---|---|---|---|---|---|\n";
  auto row = [&](int spp, const PathRun& p, double rmse, double err) {
    const std::vector<double> m = hairMean(p.frame);
    r.md << "| " << spp << " | " << fmt(p.seconds) << " | " << fmt(1e-6 * raysPerSecond(p.frame))
         << " | " << fmt(rmse, 5) << " | (" << fmt(m[0], 4) << ", " << fmt(m[1], 4) << ", "
         << fmt(m[2], 4) << ") | " << fmt(100.0 * err, 2) << " % |\n";
    r.report["pathref"][std::to_string(spp)] = {{"seconds", p.seconds},
                                                {"rays_per_s", raysPerSecond(p.frame)},
                                                {"rmse", rmse},
                                                {"mean_error", err}};
    std::fprintf(stderr, "pathref %d spp: %.2f s, RMSE %.5f, mean colour error %.2f %%\n", spp,
                 p.seconds, rmse, 100.0 * err);
  };
  for (int spp : spps) {
    const PathRun p = trace(r.b.renderer, s, spp, 1u);
    double se = 0.0;
    for (std::size_t i = 0; i < P; ++i)
      for (int c = 0; c < 3; ++c) {
        const double d = p.frame.color.rgba[4 * i + c] - ref.frame.color.rgba[4 * i + c];
        se += d * d;
      }
    const std::vector<double> m = hairMean(p.frame);
    double err = 0.0;
    for (int c = 0; c < 3; ++c)
      err = std::max(err, std::fabs(m[c] - refMean[c]) / std::max(refMean[c], 1e-12));
    row(spp, p, std::sqrt(se / (3.0 * static_cast<double>(P))), err);
  }
  row(refSpp, ref, 0.0, 0.0);
}

}  // namespace clhair::bench
