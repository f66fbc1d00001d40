// fit_mesh.cpp — `clhair fit-mesh`: a hair mesh fitted to a strand file (host/fit/,
// docs/fitting.md), written as a hair-mesh file with an optional JSON report; prints the
// fit's size, its distance to the input strands and its time.
#include <cstdio>
#include <filesystem>

#include "clhair/hair_mesh.h"
#include "clhair/triangle_mesh.h"
#include "commands.h"
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
                  "head mesh (.obj, in the strand file's units and axes): the root layer is "
                  "placed on it");
  cmd->add_option("--appearance", f.appearance,
                  "take colours and fibre BSDF from this hair-mesh file (default: the strand "
                  "file's colours when it has them)");
  cmd->add_option("--fibre-width", f.options.fibreWidth,
                  "fibre width (file units, 0..1 and at most a tenth of the median strand length; "
                  "default: the file's thickness, else 7e-5)");
  cmd->add_option("--shape-weight", f.options.shapeWeight,
                  "weight of strand shape against root position when clustering (default 1)");
  cmd->add_option("--seed", f.options.seed, "the mesh's seed (default 1)");
  cmd->add_option("--error-sample", f.options.errorSample,
                  "measure the distance of this many input strands, evenly spread (0: all; at most "
                  "2^31)");
  cmd->add_flag("-q,--quiet", f.quiet, "print nothing on success");
  return cmd;
}

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
  const StrandGroom groom = loadStrandGroom(f.input, 16ull << 30, &skipped, &warnings);
  for (const std::string& w : warnings) std::fprintf(stderr, "clhair: warning: %s\n", w.c_str());
  if (skipped > 0)
    std::fprintf(stderr, "clhair: warning: %s: %llu single-point strands left out\n",
                 f.input.c_str(), static_cast<unsigned long long>(skipped));
  FitResult r = fitHairMesh(groom, f.options);
  if (!f.appearance.empty()) {
    const float width = r.mesh.appearance.strandWidth;
    r.mesh.appearance = look.appearance;
    if (f.options.fibreWidth > 0.0f) r.mesh.appearance.strandWidth = width;
  }
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
  std::printf("  time: %.2f s\n", rep.seconds);
  for (const std::string& n : rep.notes) std::printf("  note: %s\n", n.c_str());
  return 0;
}

}  // namespace clhair::cli
