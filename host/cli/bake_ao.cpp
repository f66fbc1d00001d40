// bake_ao.cpp — `clhair bake-ao`: ambient occlusion of a hair mesh's layer vertices, baked
// on the device and written into a copy of the hair-mesh file.
#include <algorithm>
#include <cstdio>

#include "clhair/hair_mesh.h"
#include "clhair/renderer.h"
#include "commands.h"
#include "io/json_util.h"
#include "io/safe_write.h"
#include "options.h"
#include "outputs.h"

namespace clhair::cli {

CLI::App* addBakeAoCommand(CLI::App& app, BakeAoFlags& f) {
  CLI::App* bakeCmd = app.add_subcommand("bake-ao", "bake ambient occlusion into a hair-mesh file");
  bakeCmd->add_option("groom", f.groomPath, "hair-mesh file")->required();
  addOutputOption(bakeCmd, f.out, "output hair-mesh file with per-vertex AO");
  return bakeCmd;
}

int cmdBakeAo(const DeviceOptions& opts, const std::string& groomPath, const std::string& out) {
  checkOutputs({{"-o", out, {".json"}, "hair-mesh (JSON)"}}, {{"the hair-mesh file", groomPath}});
  HairMesh mesh = loadHairMesh(groomPath);
  Device dev = Device::open(opts);
  Renderer renderer(dev);
  mesh.ao = renderer.bakeAmbientOcclusion(mesh);
  saveHairMesh(mesh, out);
  float lo = 1.0f, hi = 0.0f;
  for (float a : mesh.ao) {
    lo = std::min(lo, a);
    hi = std::max(hi, a);
  }
  std::printf("%s: AO of %zu layer vertices, %.3f..%.3f\n", out.c_str(), mesh.ao.size(), lo, hi);
  return 0;
}

}  // namespace clhair::cli
