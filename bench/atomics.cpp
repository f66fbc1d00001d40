// atomics.cpp — the benchmark's atomics section (clhair_bench --only atomics):
// 64-bit atom_min throughput with and without the load skip, and each table1 MSAA-1 raster time as
// a multiple of that floor.
#include "harness.h"

#include <algorithm>
#include <vector>

#include "cl/device_impl.h"

namespace clhair::bench {

namespace {

// ns per 64-bit atom_min issued on this device (coherent addresses); returns {plain, skip}
std::pair<double, double> atomicProbe(Device::Impl& d, std::size_t words, int repeats, json& out) {
  cl::Kernel k(d.program("bench.cl"), "bench_atomic_min");
  cl::Buffer target(d.context, CL_MEM_READ_WRITE, words * sizeof(cl_ulong));
  const cl_uint perItem = 16;
  const std::size_t items = words / 4;  // 4 attempts per word per pass on average
  double result[2];
  for (int skip = 0; skip < 2; ++skip) {
    std::vector<double> ms;
    for (int r = 0; r < repeats + 1; ++r) {
      d.queue.enqueueFillBuffer(target, ~cl_ulong(0), 0, words * sizeof(cl_ulong));
      k.setArg(0, target);
      k.setArg(1, static_cast<cl_uint>(words));
      k.setArg(2, perItem);
      k.setArg(3, static_cast<cl_uint>(skip));
      cl::Event e;
      d.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(items), cl::NullRange, nullptr,
                                   &e);
      e.wait();
      double t = (e.getProfilingInfo<CL_PROFILING_COMMAND_END>() -
                  e.getProfilingInfo<CL_PROFILING_COMMAND_START>()) *
                 1e-6;
      if (r > 0) ms.push_back(t);  // the first run warms up
    }
    Stats s = summarize(ms);
    double attempts = static_cast<double>(items) * perItem;
    result[skip] = s.median * 1e6 / attempts;
    out[skip ? "load_skip" : "plain"] = {{"median_ms", s.median},
                                         {"attempts", attempts},
                                         {"ns_per_attempt", result[skip]},
                                         {"attempts_per_s", attempts / (s.median * 1e-3)}};
  }
  return {result[0], result[1]};
}

}  // namespace

void runAtomics(Run& r) {
  json probe;
  auto [plain, skip] =
      atomicProbe(*r.dev.impl(), static_cast<std::size_t>(r.opt.width) * r.opt.height,
                  std::max(r.opt.runs, 3), probe);
  r.report["atomic_probe"] = probe;
  r.md << "\n## Atomic floor\n\n64-bit `atom_min` on " << r.opt.width << "x" << r.opt.height
       << " words, coherent addresses, 4 attempts per word: " << fmt(plain, 3)
       << " ns per attempt (plain), " << fmt(skip, 3)
       << " ns with the load skip.\n\n| configuration | strand pass ms | atomics issued | floor "
          "ms "
          "(issued x plain) | raster / floor |\n|---|---|---|---|---|\n";
  for (const auto& [name, m] : r.msaa1Rows) {
    double floorMs = m.counts.atomicsIssued * plain * 1e-6;
    double ratio = floorMs > 0 ? stageMedian(m, "strands") / floorMs : 0.0;
    r.md << "| " << name << " | " << fmt(stageMedian(m, "strands")) << " | "
         << m.counts.atomicsIssued << " | " << fmt(floorMs, 3) << " | " << fmt(ratio, 1) << "x |\n";
    r.report["raster_over_atomic_floor"][name] = ratio;
  }
}

}  // namespace clhair::bench
