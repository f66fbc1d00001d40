// groom.cpp — `clhair groom`: a generated hair mesh (a preset, optionally with another
// strand count) written as a hair-mesh file.
#include <cstdio>

#include "clhair/error.h"
#include "clhair/hair_mesh.h"
#include "commands.h"
#include "groom/presets.h"
#include "io/json_util.h"
#include "io/safe_write.h"
#include "options.h"
#include "outputs.h"

namespace clhair::cli {

CLI::App* addGroomCommand(CLI::App& app, GroomFlags& f) {
  CLI::App* groom = app.add_subcommand("groom", "write a generated hair mesh");
  groom->add_option("--preset", f.preset, "long_wavy, curly_medium, fur_sphere or tiny")
      ->required();
  addOutputOption(groom, f.out, "output hair-mesh file (.json)");
  groom->add_option("--strands", f.strands, "override the strand count");
  return groom;
}

int cmdGroom(const GroomFlags& f) {
  const std::string& preset = f.preset;
  const std::string& out = f.out;
  const long long strands = f.strands;
  if (f.strandsGiven && strands < 0)
    throw Error("--strands " + std::to_string(strands) +
                " is negative; expected a strand count 0..50000000");
  checkOutputs({{"-o", out, {".json"}, "hair-mesh (JSON)"}}, {});
  HairMesh m = makeGroomPreset(preset);
  if (strands >= 0) m.strandCount = strands;
  m.lod.enabled = true;  // a groom file draws with LOD unless it says otherwise
  saveHairMesh(m, out);
  std::printf("%s: %s, %d bundles, %d layers, %lld strands\n", out.c_str(), m.name.c_str(),
              static_cast<int>(m.faces.size()), m.layerCount,
              static_cast<long long>(m.strandCount));
  return 0;
}

}  // namespace clhair::cli
