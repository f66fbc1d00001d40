// main.cpp — clhair_bench: speed of the pipeline on one device, reported side by side.
//
// Sections run in the order of the table below, all by default or one chosen with --only;
// each lives in a file of its own (bench/<name>.cpp; crowd, lodfar and throughput through
// bench/wrappers.cpp) and says there what it measures. The harness (bench/harness.h) holds
// the options, the device, timing and medians and the report. Adding a section: a new file
// with `void runName(Run& r)`, its declaration and one row in the table.
// Stage timings come from OpenCL profiling events (device time per stage); frames are also
// timed by wall clock (what a user waits for: uploads, read-backs and host work included);
// compile time is reported apart. Output: bench.json, bench.csv and bench.md in --out,
// tagged with device, driver and git revision; the markdown is also printed.
#include <cstdio>
#include <exception>

#include "cl/opencl.h"
#include "harness.h"

namespace clhair::bench {

void runTable1(Run& r);
void runAtomics(Run& r);
void runDispatch(Run& r);
void runScaling(Run& r);
void runQuality(Run& r);
void runLook(Run& r);
void runTemporal(Run& r);
void runExplicit(Run& r);
void runChildren(Run& r);
void runCrowd(Run& r);
void runMesh(Run& r);
void runFloor(Run& r);
void runSequences(Run& r);
void runLodFar(Run& r);
void runThroughput(Run& r);
void runPathConvergence(Run& r);
void runPixels(Run& r);

struct Section {
  const char* name;
  void (*run)(Run&);
  const char* alsoFor = nullptr;  // another --only that needs this section's rows first
};

const Section kSections[] = {
    {"table1", runTable1, "atomics"},  // its MSAA-1 rows feed the atomic floor
    {"atomics", runAtomics},
    {"dispatch", runDispatch},
    {"scaling", runScaling},
    {"quality", runQuality},
    {"look", runLook},
    {"temporal", runTemporal},
    {"explicit", runExplicit},
    {"children", runChildren},
    {"crowd", runCrowd},
    {"mesh", runMesh},
    {"floor", runFloor},
    {"sequences", runSequences},
    {"lodfar", runLodFar},
    {"throughput", runThroughput},
    {"pathref", runPathConvergence},
    {"pixels", runPixels},
};

}  // namespace clhair::bench

int main(int argc, char** argv) {
  using namespace clhair::bench;
  Options options;
  if (const std::optional<int> status = parseOptions(argc, argv, options)) return *status;
  try {
    Run run(options);
    const std::string& only = options.only;
    for (const Section& s : kSections)
      if (only.empty() || only == s.name || (s.alsoFor && only == s.alsoFor)) s.run(run);
    run.write();
  } catch (const cl::Error& e) {
    std::fprintf(stderr, "clhair_bench: error: OpenCL %s (%d)\n", e.what(), e.err());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "clhair_bench: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
