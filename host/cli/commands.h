// commands.h — the subcommands of `clhair` other than render (render.h), one source file
// each: devices.cpp, groom.cpp, bake_ao.cpp, bake_visibility.cpp, export_strands.cpp,
// compare.cpp and fit_mesh.cpp. Each adds itself and its options to the command (add...),
// holds what the command line gave in its flags, and runs (cmd...: 0 on success, else it
// throws the Error main.cpp reports as one line).
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "clhair/device.h"
#include "clhair/fit.h"
#include "groom/visibility_bake.h"
#include "metrics/image_metrics.h"

namespace clhair::cli {

// ---- devices (devices.cpp) ------------------------------------------------------------------

CLI::App* addDevicesCommand(CLI::App& app);
int cmdDevices(const DeviceOptions& opts);

// ---- groom (groom.cpp) ----------------------------------------------------------------------

struct GroomFlags {
  std::string preset, out;
  long long strands = -1;     // --strands; -1: the preset's
  bool strandsGiven = false;  // --strands given (a negative count is refused)
};
CLI::App* addGroomCommand(CLI::App& app, GroomFlags& f);
int cmdGroom(const GroomFlags& f);

// ---- bake-ao (bake_ao.cpp) ------------------------------------------------------------------

struct BakeAoFlags {
  std::string groomPath, out;
};
CLI::App* addBakeAoCommand(CLI::App& app, BakeAoFlags& f);
int cmdBakeAo(const DeviceOptions& opts, const std::string& groomPath, const std::string& out);

// ---- bake-visibility (bake_visibility.cpp) ----------------------------------------------------

// `clhair bake-visibility`'s options as given on the command line (defaults:
// VisibilityBakeOptions).
struct BakeVisibilityFlags {
  std::string scenePath, out;  // the scene file and -o
  int groom = 0;
  int rays = static_cast<int>(VisibilityBakeOptions{}.raysPerPoint);
  int perCell = static_cast<int>(VisibilityBakeOptions{}.pointsPerCell);
  int maxEvents = static_cast<int>(VisibilityBakeOptions{}.maxEvents);
  bool verbose = false;
  std::string directions = "per-point";
  int cellStride = 1;
  std::string transmittanceOut;
};
CLI::App* addBakeVisibilityCommand(CLI::App& app, BakeVisibilityFlags& f);
int cmdBakeVisibility(const DeviceOptions& opts, const std::string& scenePath,
                      const std::string& out, const BakeVisibilityFlags& f);

// ---- export-strands (export_strands.cpp) ------------------------------------------------------

struct ExportFlags {
  std::string groomPath, out;
  int groom = 0;  // --groom: the scene's groom
};
CLI::App* addExportCommand(CLI::App& app, ExportFlags& f);
int cmdExport(const DeviceOptions& opts, const std::string& groomPath, const std::string& out,
              int groom);

// ---- compare (compare.cpp) ------------------------------------------------------------------

struct CompareFlags {
  std::string reference, test;  // images A and B
  std::string errorMap;
  double ppd = kFlipDefaultPpd;
  bool json = false;
};
CLI::App* addCompareCommand(CLI::App& app, CompareFlags& f);
int cmdCompare(const std::string& pathA, const std::string& pathB, const CompareFlags& f);

// ---- fit-mesh (fit_mesh.cpp) ----------------------------------------------------------------

struct FitMeshFlags {
  std::string input, output, report, head, appearance;
  std::string scale;  // --scale: a number or "auto"; empty: 1 (the file is in metres)
  FitOptions options;
  bool quiet = false;
};
CLI::App* addFitMeshCommand(CLI::App& app, FitMeshFlags& f);
int cmdFitMesh(FitMeshFlags f);

}  // namespace clhair::cli
