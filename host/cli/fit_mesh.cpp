// fit_mesh.cpp — `clhair fit-mesh`: a hair mesh fitted to a strand file (host/fit/,
// docs/fitting.md), written as a hair-mesh file with an optional JSON report; prints the
// fit's size, its distance to the input strands and its time.
//
// --scale (a number, or "auto": a scene's rule, io/auto_scale.h) takes the file to metres
// before the fit, so the fibre width (--fibre-width, metres, checked against human hair's
// range), the distances reported and the mesh written are all in metres.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>

#include "clhair/error.h"
#include "clhair/hair_mesh.h"
#include "clhair/triangle_mesh.h"
#include "commands.h"
#include "io/auto_scale.h"
#include "io/json_util.h"
#include "options.h"
#include "outputs.h"

namespace clhair::cli {

CLI::App* addFitMeshCommand(CLI::App& app, FitMeshFlags& f) {
  CLI::App* cmd = app.add_subcommand(
      "fit-mesh", "fit a hair mesh to a strand file (.hair, .data, .tfx; docs/fitting.md)");
  cmd->add_option("strands", f.input, "strand file")->required();
  addOutputOption(cmd, f.output, "output hair-mesh file (.json)");
  cmd->add_option("--bundles", f.options.bundles,
                  "bundles to aim for, 1.." + std::to_string(kFitMaxBundles) +
                      " (default: one per 64 strands)");
  cmd->add_option("--layers", f.options.layers, "layers per bundle, 2..64 (default 16)");
  cmd->add_option("--report", f.report, "write the fit report (JSON) here");
  cmd->add_option("--head", f.head,
                  "head mesh (.obj, in the strand file's units and axes, scaled with it): the "
                  "root layer is placed on it");
  cmd->add_option("--appearance", f.appearance,
                  "take colours and fibre BSDF from this hair-mesh file (default: the strand "
                  "file's colours when it has them)");
  cmd->add_option("--scale", f.scale,
                  "file units to metres before the fit: a number (0.01 for centimetres) or "
                  "auto (the roots' extent made 0.18 m, as a scene's \"scale\": \"auto\"); "
                  "default 1");
  cmd->add_option("--fibre-width", f.options.fibreWidth,
                  "fibre width in metres, after --scale, 1e-6..1e-3 and at most a tenth of the "
                  "median strand length (default: the file's thickness, else 7e-5)");
  cmd->add_option("--shape-weight", f.options.shapeWeight,
                  "weight of strand shape against root position when clustering (default 1)");
  cmd->add_option("--seed", f.options.seed, "the mesh's seed (default 1)");
  cmd->add_option("--error-sample", f.options.errorSample,
                  "measure the distance of this many input strands, evenly spread (0: all; at most "
                  "2^31)");
  cmd->add_flag("-q,--quiet", f.quiet, "print nothing on success");
  return cmd;
}

namespace {

constexpr float kMinFibreWidth = 1e-6f, kMaxFibreWidth = 1e-3f;

// Takes the groom to metres: --scale's number, or "auto"; empty: the file is in metres, and
// roots spanning less than 3 cm or more than 1.5 m get a warning. Returns the factor.
float toMetres(StrandGroom& g, const std::string& flag, const std::string& path) {
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  addRootBounds(g, lo, hi);
  float extent = 0.0f;
  const float autoFactor = autoScaleFactor(lo, hi, &extent);
  float s = 1.0f;
  if (flag == "auto") {
    s = autoFactor;
  } else if (!flag.empty()) {
    char* end = nullptr;
    const double v = std::strtod(flag.c_str(), &end);
    if (end != flag.c_str() + flag.size() || !(v >= 1e-6 && v <= 1e6))
      throw Error("--scale is \"" + flag + "\", expected a number in 1e-6..1e6 or auto");
    s = static_cast<float>(v);
  } else if (extent > 0.0f && (extent < 0.03f || extent > 1.5f)) {
    std::fprintf(stderr,
                 "clhair: warning: %s: its roots span %g units, not a head's 0.1-0.3 m: are "
                 "its units metres? --scale 0.01 for centimetres, or --scale auto (%g)\n",
                 path.c_str(), static_cast<double>(extent), static_cast<double>(autoFactor));
  }
  if (s == 1.0f) return s;
  for (glm::vec3& p : g.points) p *= s;
  for (float& t : g.thickness) t *= s;
  return s;
}

}  // namespace

int cmdFitMesh(FitMeshFlags f) {
  // before any work: the mesh and the report go to new files, neither is an input
  checkOutputs({{"-o", f.output, {".json"}, "hair-mesh (JSON)"},
                {"--report", f.report, {".json"}, "fit report (JSON)"}},
               {{"the strand file", f.input},
                {"the head mesh", f.head},
                {"the appearance file", f.appearance}});
  TriangleMesh head;
  if (!f.head.empty()) {
    head = loadTriangleMesh(f.head);
    f.options.head = &head;
  }
  HairMesh look;
  if (!f.appearance.empty()) look = loadHairMesh(f.appearance);
  std::uint64_t skipped = 0;
  std::vector<std::string> warnings;
  if (f.options.fibreWidth != 0.0f &&
      !(f.options.fibreWidth >= kMinFibreWidth && f.options.fibreWidth <= kMaxFibreWidth))
    throw Error("--fibre-width " + std::to_string(f.options.fibreWidth) +
                " is outside 1e-06..0.001 m; it is in metres after --scale (human hair is "
                "about 7e-05)");
  StrandGroom groom = loadStrandGroom(f.input, 16ull << 30, &skipped, &warnings);
  for (const std::string& w : warnings) std::fprintf(stderr, "clhair: warning: %s\n", w.c_str());
  if (skipped > 0)
    std::fprintf(stderr, "clhair: warning: %s: %llu single-point strands left out\n",
                 f.input.c_str(), static_cast<unsigned long long>(skipped));
  const float scale = toMetres(groom, f.scale, f.input);
  for (glm::vec3& p : head.positions) p *= scale;  // the head is in the strand file's units
  FitResult r = fitHairMesh(groom, f.options);
  // a TressFX file draws its runtime's follow hairs around each guide (as a scene does):
  // the mesh grows as many strands as the file draws
  if (lowerExtension(f.input) == ".tfx" && r.mesh.strandCount > 0) {
    r.mesh.strandCount *= 1 + static_cast<std::int64_t>(kTressFxFollowHairs);
    r.report.notes.push_back("the TressFX file draws " + std::to_string(kTressFxFollowHairs) +
                             " follow hairs per guide: the mesh grows " +
                             std::to_string(r.mesh.strandCount) + " strands");
  }
  if (!f.appearance.empty()) {
    const float width = r.mesh.appearance.strandWidth;
    r.mesh.appearance = look.appearance;
    if (f.options.fibreWidth > 0.0f) r.mesh.appearance.strandWidth = width;
  }
  r.mesh.lod.enabled = true;  // a groom file draws with LOD unless it says otherwise
  saveHairMesh(r.mesh, f.output);
  std::error_code ec;
  r.report.strandFileBytes = std::filesystem::file_size(f.input, ec);
  if (ec) r.report.strandFileBytes = 0;
  r.report.meshFileBytes = std::filesystem::file_size(f.output, ec);
  if (ec) r.report.meshFileBytes = 0;
  if (!f.report.empty()) writeFitReport(r.report, f.report);
  if (f.quiet) return 0;
  const FitReport& rep = r.report;
  std::printf("%s: %d bundles, %d layers, %d vertices, %zu strands (%zu in)\n", f.output.c_str(),
              rep.bundles, rep.layers, rep.vertices, rep.strandsOut, rep.strandsIn);
  if (rep.error.strands > 0)
    std::printf(
        "  distance to the nearest generated strand: mean %.3g m (%.2f fibre widths), "
        "95th percentile %.3g m (%.2f)\n",
        rep.error.meanM, rep.error.meanWidths, rep.error.p95M, rep.error.p95Widths);
  if (rep.strandFileBytes > 0)
    std::printf(
        "  size: %llu bytes, %.3f %% of the strand file\n",
        static_cast<unsigned long long>(rep.meshFileBytes),
        100.0 * static_cast<double>(rep.meshFileBytes) / static_cast<double>(rep.strandFileBytes));
  if (scale != 1.0f)
    std::printf("  scale: %g (file units to metres)\n", static_cast<double>(scale));
  std::printf("  time: %.2f s\n", rep.seconds);
  for (const std::string& n : rep.notes) std::printf("  note: %s\n", n.c_str());
  return 0;
}

}  // namespace clhair::cli
