// bake_visibility.cpp — `clhair bake-visibility`: a groom's spherical visibility for
// self-shadowing, traced with Embree (groom/visibility_bake.h) and written as a .clhvis file;
// with --transmittance-out also the study table of per-direction transmittance, and with -v
// each phase's wall and CPU time.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>

#include "clhair/error.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "clhair/visibility_sh.h"
#include "commands.h"
#include "io/binary_file.h"
#include "io/json_util.h"
#include "io/safe_write.h"
#include "options.h"
#include "outputs.h"

namespace clhair::cli {

namespace {

// The study mode's table: "CLHTRN01", u32 absorptions, cells, directions, the absorptions as
// f32, then f32 [absorption][cell][direction] (little-endian; scripts/compare-visibility.py).
void writeTransmittance(const VisibilityBakeStats& st, std::uint32_t rays,
                        const std::string& path) {
  std::string out("CLHTRN01", 8);
  appendU32(out, kTransmittanceAbsorptions);
  appendU32(out, CLH_VIS_CELLS);
  appendU32(out, rays);
  for (float a : kTransmittanceAbsorption) appendF32(out, a);
  for (float t : st.transmittance) appendF32(out, t);
  writeTextAtomically(path, out);
}

}  // namespace

CLI::App* addBakeVisibilityCommand(CLI::App& app, BakeVisibilityFlags& vf) {
  CLI::App* visCmd = app.add_subcommand(
      "bake-visibility",
      "bake a groom's spherical visibility for self-shadowing (Embree; docs/scene-format.md)");
  visCmd->add_option("scene", vf.scenePath, "scene file: the groom and its head")->required();
  addOutputOption(visCmd, vf.out, "output baked visibility file (.clhvis)");
  visCmd->add_option("--groom", vf.groom, "index of the groom in the scene (default 0)");
  visCmd->add_option("--rays", vf.rays,
                     "rays per sample point (default " + std::to_string(vf.rays) + ")");
  visCmd->add_option(
      "--points-per-cell", vf.perCell,
      "sample points per (u, v, w) cell (default " + std::to_string(vf.perCell) + ")");
  visCmd->add_option("--max-events", vf.maxEvents,
                     "a ray's scattering events are clamped at this count (1.." +
                         std::to_string(kMaxEventsLimit) + ", default " +
                         std::to_string(vf.maxEvents) +
                         "; about 5 / absorption is closest to the true shadowing)");
  visCmd->add_flag("-v,--verbose", vf.verbose,
                   "print each phase's wall and CPU time to stderr (the tracing phase also "
                   "its threads' time waiting for a core)");
  visCmd->add_option("--directions", vf.directions,
                     "per-point (default): each sample point its own stratified set of directions; "
                     "per-cell: one set per cell dealt out to its points");
  visCmd->add_option("--cell-stride", vf.cellStride,
                     "bake only about one occupied cell in N (by hash), the rest left zero: a "
                     "sample of the table for estimator studies (default 1: every cell)");
  visCmd->add_option("--transmittance-out", vf.transmittanceOut,
                     "estimator study: trace every point in the same --rays directions and also "
                     "write each cell's mean transmittance per direction before the SH fit "
                     "(scripts/compare-visibility.py --transmittance)");
  return visCmd;
}

int cmdBakeVisibility(const DeviceOptions& opts, const std::string& scenePath,
                      const std::string& out, const BakeVisibilityFlags& f) {
  const int rays = f.rays, perCell = f.perCell, groom = f.groom;
  if (rays < 1 || rays > 4096) throw Error("--rays must be 1..4096, not " + std::to_string(rays));
  if (perCell < 1 || perCell > 64)
    throw Error("--points-per-cell must be 1..64, not " + std::to_string(perCell));
  if (f.maxEvents < 1 || f.maxEvents > static_cast<int>(kMaxEventsLimit))
    throw Error("--max-events must be 1.." + std::to_string(kMaxEventsLimit) + ", not " +
                std::to_string(f.maxEvents));
  if (f.directions != "per-cell" && f.directions != "per-point")
    throw Error("--directions must be per-cell or per-point, not \"" + f.directions + "\"");
  if (f.cellStride < 1)
    throw Error("--cell-stride must be 1 or more, not " + std::to_string(f.cellStride));
  if (!f.transmittanceOut.empty() && f.directions != "per-point")
    throw Error("--transmittance-out traces per-point directions, not --directions per-cell");
  checkOutputs({{"-o", out, {".clhvis"}, "baked visibility"},
                {"--transmittance-out", f.transmittanceOut, {}, "transmittance table"}},
               {{"the scene", scenePath}});
  VisibilityBakeStats st;
  BakePhaseTimer timer(&st);
  const Scene scene = loadScene(scenePath);
  timer.finish("scene");
  // the files the scene names are known once it is read, before the bake
  std::vector<NamedFile> inputs;
  for (const std::string& file : scene.files) inputs.push_back({"a file the scene reads", file});
  checkNotAnInput("-o", out, inputs);
  if (!f.transmittanceOut.empty())
    checkNotAnInput("--transmittance-out", f.transmittanceOut, inputs);
  if (groom < 0 || static_cast<std::size_t>(groom) >= scene.grooms.size())
    throw Error(scenePath + ": --groom " + std::to_string(groom) +
                " does not exist, the scene has " + std::to_string(scene.grooms.size()) +
                " groom(s)");
  const GroomInstance& gi = scene.grooms[static_cast<std::size_t>(groom)];
  if (gi.strands && gi.strands->appearance.useFileColor && !gi.strands->colors.empty())
    throw Error(scenePath + ": groom \"" + gi.name +
                "\" is drawn with its file colours, whose G-buffer words carry no styling uv to "
                "look a bake up by");
  Device dev = Device::open(opts);
  Renderer renderer(dev);
  timer.finish("device");
  VisibilityBakeOptions o;
  o.raysPerPoint = static_cast<std::uint32_t>(rays);
  o.pointsPerCell = static_cast<std::uint32_t>(perCell);
  o.maxEvents = static_cast<std::uint32_t>(f.maxEvents);
  o.directions = f.directions == "per-point" ? VisibilityBakeOptions::Directions::PerPoint
                                             : VisibilityBakeOptions::Directions::PerCell;
  o.cellStride = static_cast<std::uint32_t>(f.cellStride);
  o.transmittance = !f.transmittanceOut.empty();
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  const VisibilityBake bake =
      bakeGroomVisibility(renderer, scene, static_cast<std::size_t>(groom), o, &st);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  BakePhaseTimer writeTimer(&st);
  writeVisibility(bake, out);
  if (o.transmittance) writeTransmittance(st, o.raysPerPoint, f.transmittanceOut);
  writeTimer.finish("write");
  if (f.verbose) {
    // one line per phase: wall, CPU over all threads, and the cores that CPU time kept busy;
    // for the split tracing, the workers' time waiting for a core (other processes' load)
    // and the rest (blocked or idle)
    for (const BakePhase& p : st.phases) {
      std::fprintf(stderr, "clhair: bake phase %-8s wall %8.2f s  cpu %8.2f s  (%.2f cores)",
                   p.name.c_str(), p.wallSeconds, p.cpuSeconds,
                   p.wallSeconds > 0.0 ? p.cpuSeconds / p.wallSeconds : 0.0);
      if (p.threads > 0 && p.waitSeconds >= 0.0)
        std::fprintf(stderr, "  %u threads: waiting for a core %.2f s, blocked or idle %.2f s",
                     p.threads, p.waitSeconds,
                     std::max(0.0, p.threads * p.wallSeconds - p.cpuSeconds - p.waitSeconds));
      std::fprintf(stderr, "\n");
    }
  }
  std::printf(
      "%s: groom \"%s\" (%u strands), %llu cells, %llu points, %llu rays, %.2f events "
      "per ray that hit, %.1f s (%.1f s of CPU time over all threads)\n",
      out.c_str(), gi.name.c_str(), bake.strands, static_cast<unsigned long long>(st.cells),
      static_cast<unsigned long long>(st.points), static_cast<unsigned long long>(st.rays),
      st.meanEvents, secs, cpu);
  if (gi.strands && gi.strands->rootUv.empty())
    std::fprintf(stderr,
                 "clhair: warning: %s has no root uv: its strands' cells are keyed by a hash, so "
                 "each cell averages unrelated strands and the bake varies only along them\n",
                 gi.name.c_str());
  return 0;
}

}  // namespace clhair::cli
