// fuzz_scene.cpp — libFuzzer target for loadScene (host/io/scene_io.cpp), which also loads
// the hair meshes a scene names.
//
// The scene is written next to a copy of assets/grooms/tiny.hairmesh.json (named
// tiny.hairmesh.json), so a relative "file" in the corpus loads a real groom. Any input
// must either be refused with a clhair::Error or load; a loaded scene evaluated at a few
// frames (sceneAtFrame) must give a cage of the mesh's size or a clhair::Error (a degenerate
// interpolated camera); anything else is a finding.
#include <cstdint>
#include <filesystem>
#include <string>

#include "clhair/error.h"
#include "clhair/scene.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::filesystem::copy_file(CLHAIR_FUZZ_GROOM, clhair::fuzz::workDir() + "/tiny.hairmesh.json",
                             std::filesystem::copy_options::overwrite_existing);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = clhair::fuzz::writeInput(data, size, "scene.json");
  try {
    const clhair::Scene s = clhair::loadScene(path);
    for (const clhair::GroomInstance& g : s.grooms)
      CLHAIR_FUZZ_CHECK((g.mesh != nullptr) != (g.strands != nullptr));
    for (double frame : {-1e9, 1.0, 7.5, 1e9}) {
      const clhair::Scene f = clhair::sceneAtFrame(s, frame);
      CLHAIR_FUZZ_CHECK(f.grooms.size() == s.grooms.size());
      for (const clhair::GroomInstance& g : f.grooms)
        CLHAIR_FUZZ_CHECK(!g.deformed || g.deformed->size() == g.mesh->positions.size());
    }
  } catch (const clhair::Error&) {
  }
  return 0;
}
