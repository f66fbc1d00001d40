// main.cpp — the `clhair` command: a thin user of the library API.
//
//   clhair devices                          list OpenCL devices and what clhair would use
//   clhair render SCENE -o OUT.png|.exr     render a scene, print per-stage times
//                [--reference [embree|raster|path] --spp N]   or its ground truth (default
//                [--path-events N]                  embree; path: multiple scattering)
//     [--frames 1-240[:STEP] -o OUT.####.exr] a frame range, one file per frame
//     [--aov rgba,z,alpha,tangent,motion,strand|all]  layers for compositing in one EXR
//     (docs/aovs.md)
//     [--views all|NAME,...]              several views of one assembly, one file per view
//                                         (%v in -o becomes the view's name)
//     [--temporal K]                      blend the hair of the K frames before (reprojected)
//   clhair groom --preset NAME -o FILE      write a generated hair mesh
//   clhair export-strands GROOM -o F.hair   write the generated strands as cyHair (F.data: USC,
//                                           F.tfx: TressFX 4.0, resampled to 4..64 points)
//   clhair compare A B [--error-map M]      PSNR, RMSE and mean FLIP of B against reference A
//   clhair fit-mesh STRANDS -o G.json       a hair mesh fitted to a strand file (docs/fitting.md)
//                [--bundles N] [--layers L] [--report R.json] [--head MESH.obj]
//
// Global options choose the device (--device, CLHAIR_DEVICE), force a sub-group backend
// (--subgroup, CLHAIR_SUBGROUP), read kernels from a source tree (--kernel-dir,
// CLHAIR_KERNEL_DIR) or print an error's details (--verbose); they go before or after the
// subcommand. Any failure prints one line "clhair: error: ..." and exits 1;
// output files are only written when the work completed.
//
// This file builds the command line from the subcommands' files (commands.h, render.h; the
// option groups they share in options.h) and dispatches to the one given; error_line.h
// prints the error line.
#include <cstdio>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>

#include "cl/cl_error.h"
#include "cl/stderr_capture.h"
#include "clhair/error.h"
#include "commands.h"
#include "error_line.h"
#include "options.h"
#include "render.h"

using namespace clhair;
using namespace clhair::cli;

int main(int argc, char** argv) {
  CLI::App app{"clhair: real-time strand hair rendering on OpenCL"};
  app.require_subcommand(1);
  // the global options may follow the subcommand too (`clhair render s.json --device 1:0`):
  // a subcommand hands the options it does not know to the whole command
  app.fallthrough();
  DeviceOptions opts;
  addDeviceOptions(app, opts);
  bool verbose = false;
  app.add_flag("--verbose", verbose,
               "on an error, print its details (the device list, a build log) after its line "
               "instead of writing them to a log file the line names");

  CLI::App* devices = addDevicesCommand(app);
  RenderFlags rf;
  CLI::App* render = addRenderCommand(app, rf);
  GroomFlags gf;
  CLI::App* groom = addGroomCommand(app, gf);
  BakeAoFlags af;
  CLI::App* bakeCmd = addBakeAoCommand(app, af);
  BakeVisibilityFlags vf;
  CLI::App* visCmd = addBakeVisibilityCommand(app, vf);
  ExportFlags ef;
  CLI::App* exportCmd = addExportCommand(app, ef);
  CompareFlags cf;
  CLI::App* compare = addCompareCommand(app, cf);
  FitMeshFlags fitFlags;
  CLI::App* fitCmd = addFitMeshCommand(app, fitFlags);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help is the one "error" that succeeds; every other parse failure is reported like
    // any other error: one line, exit 1 (not CLI11's own codes and two-line message).
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    const std::string unknown = unknownSubcommand(app, argc, argv);
    std::fprintf(stderr, "clhair: error: %s (see clhair --help)\n",
                 unknown.empty() ? oneLine(e.what()).c_str() : unknown.c_str());
    return 1;
  }
  try {
    checkFlagRules(app);
  } catch (const Error& e) {
    reportError(e.what(), "", verbose);
    return 1;
  }
  noteRenderFlagsGiven(*render, rf);
  gf.strandsGiven = groom->count("--strands") > 0;
  captureDriverOutput(true);  // a compiler's own lines go into an error's details
  try {
    DeviceOptions resolved = DeviceOptions::fromEnvironment(opts);
    if (*devices) return cmdDevices(resolved);
    if (*render) return cmdRender(resolved, rf.scenePath, rf.out, rf);
    if (*groom) return cmdGroom(gf);
    if (*exportCmd) return cmdExport(resolved, ef.groomPath, ef.out, ef.groom);
    if (*bakeCmd) return cmdBakeAo(resolved, af.groomPath, af.out);
    if (*visCmd) return cmdBakeVisibility(resolved, vf.scenePath, vf.out, vf);
    if (*compare) return cmdCompare(cf.reference, cf.test, cf);
    if (*fitCmd) return cmdFitMesh(fitFlags);
  } catch (const Error& e) {
    reportError(e.what(), e.details(), verbose);
    return 1;
  } catch (const cl::Error& e) {
    reportError(std::string("OpenCL call ") + e.what() + " failed with " + clErrorName(e.err()) +
                    " (" + std::to_string(e.err()) + ")",
                "", verbose);
    return 1;
  } catch (const std::exception& e) {
    reportError(e.what(), "", verbose);
    return 1;
  }
  return 1;
}
