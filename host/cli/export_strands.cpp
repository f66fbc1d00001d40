// export_strands.cpp — `clhair export-strands`: the strands clhair generates from a hair mesh,
// a strand file or a scene's groom (as drawn, children included), written as cyHair (.hair),
// USC-HairSalon (.data), TressFX 4.0 (.tfx, resampled to one point count) or PLY (.ply).
#include <cstdio>
#include <fstream>
#include <memory>

#include <nlohmann/json.hpp>

#include "clhair/error.h"
#include "clhair/hair_mesh.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "commands.h"
#include "io/cyhair.h"
#include "io/json_util.h"
#include "io/ply_strands.h"
#include "io/regular_file.h"
#include "io/safe_write.h"
#include "io/tressfx.h"
#include "io/usc_hair.h"
#include "options.h"
#include "outputs.h"

namespace clhair::cli {

namespace {

// The strands export-strands writes: a hair mesh's generated strands (root/tip colours), a
// strand file's (its colours), or a scene groom's as drawn at full detail, children included
// (in the groom's object space).
CyHair exportSource(Renderer& renderer, std::uint64_t maxAlloc, const std::string& path,
                    int groom) {
  const std::string ext = lowerExtension(path);
  const bool strandFile =
      ext == ".hair" || ext == ".data" || ext == ".tfx" || ext == ".ply" || ext == ".bin";
  bool scene = false;
  if (!strandFile && ext == ".json") {
    std::ifstream in(path);
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    scene = j.is_object() && j.contains("grooms");
  }
  if (!scene && groom != 0)
    throw Error("--groom " + std::to_string(groom) + ": " + path + " is not a scene file");
  std::shared_ptr<const StrandGroom> strands;
  std::shared_ptr<const HairMesh> mesh;
  std::string name;
  if (strandFile) {
    strands = std::make_shared<const StrandGroom>(loadStrandGroom(path, maxAlloc));
  } else if (scene) {
    const Scene sc = loadScene(path, maxAlloc);
    if (groom < 0 || static_cast<std::size_t>(groom) >= sc.grooms.size())
      throw Error(path + ": --groom " + std::to_string(groom) + " does not exist, the scene has " +
                  std::to_string(sc.grooms.size()) + " groom(s)");
    strands = sc.grooms[static_cast<std::size_t>(groom)].strands;
    mesh = sc.grooms[static_cast<std::size_t>(groom)].mesh;
  } else {
    mesh = std::make_shared<const HairMesh>(loadHairMesh(path));
  }
  CyHair h;
  StrandSet s;
  if (strands) {
    s = renderer.generateStrands(*strands);
    name = strands->name;
    h.defaultThickness = strands->appearance.strandWidth;
  } else {
    s = renderer.generateStrands(*mesh);
    name = mesh->name;
    h.defaultThickness = mesh->appearance.strandWidth;
  }
  h.segments.reserve(s.pointCounts.size());
  for (std::uint32_t c : s.pointCounts) h.segments.push_back(c - 1);
  h.points = s.points;
  h.colors.reserve(s.points.size());
  if (mesh) {
    for (float w : s.w) {
      glm::vec3 c =
          mesh->appearance.rootColor + (mesh->appearance.tipColor - mesh->appearance.rootColor) * w;
      h.colors.insert(h.colors.end(), {c.x, c.y, c.z});
    }
  } else if (!s.look.empty() && strands->appearance.useFileColor && !strands->colors.empty()) {
    for (std::size_t i = 0; i < s.look.size(); i += 4)
      h.colors.insert(h.colors.end(), {s.look[i], s.look[i + 1], s.look[i + 2]});
  }
  h.info = "clhair export-strands: " + name;
  return h;
}

}  // namespace

CLI::App* addExportCommand(CLI::App& app, ExportFlags& f) {
  CLI::App* exportCmd = app.add_subcommand("export-strands",
                                           "write the generated strands as a cyHair .hair file "
                                           "(USC-HairSalon when the name ends in .data, "
                                           "TressFX 4.0 for .tfx, PLY for .ply)");
  exportCmd
      ->add_option("groom", f.groomPath,
                   "hair-mesh file, strand file, or scene (its groom as drawn, children "
                   "included)")
      ->required();
  addOutputOption(exportCmd, f.out, "output .hair, .data, .tfx or .ply file");
  exportCmd->add_option("--groom", f.groom, "the scene's groom to export (default 0)");
  return exportCmd;
}

int cmdExport(const DeviceOptions& opts, const std::string& groomPath, const std::string& out,
              int groom) {
  const std::string ext = lowerExtension(out);
  if (ext != ".hair" && ext != ".data" && ext != ".tfx" && ext != ".ply")
    throw Error(out + ": " +
                (ext.empty() ? std::string("has no extension to choose a strand format by")
                             : "no strand-file writer for extension \"" + ext + "\"") +
                " (use .hair: cyHair, .data: USC-HairSalon, .tfx: TressFX 4.0, .ply: PLY)");
  checkOutputs({{"-o", out, {}, "strand file"}}, {{"the groom file", groomPath}});
  { RegularFile groomFile(groomPath, "groom"); }  // named before the device opens
  Device dev = Device::open(opts);
  Renderer renderer(dev);
  CyHair h = exportSource(renderer, dev.info().maxAlloc, groomPath, groom);
  if (ext == ".tfx") {
    // TressFX needs one point count for all strands, and AMD's runtime a power of two in
    // 4..64: resample along the arc length (points only, like USC-HairSalon).
    TressFxHair t;
    const std::uint32_t n = tressFxVertexCount(h);
    t.hair = resampleStrands(h, n);
    writeTressFx(t, out);
    std::printf("%s: %zu strands, resampled to %u points each (TressFX 4.0)\n", out.c_str(),
                h.segments.size(), n);
    return 0;
  }
  if (ext == ".data")
    writeUscHair(h, out);  // points only: the format has no colour or thickness
  else if (ext == ".ply")
    writePlyStrands(h, out);  // points and colours
  else
    writeCyHair(h, out);
  std::printf("%s: %zu strands, %zu points\n", out.c_str(), h.segments.size(), h.points.size() / 3);
  return 0;
}

}  // namespace clhair::cli
