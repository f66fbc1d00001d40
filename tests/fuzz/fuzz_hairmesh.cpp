// fuzz_hairmesh.cpp — libFuzzer target for loadHairMesh (host/io/hair_mesh_io.cpp).
//
// Any input must either be refused with a clhair::Error or load into a mesh that passes
// validateHairMesh; any other exception, sanitizer report or crash is a finding.
#include <cstdint>
#include <string>

#include "clhair/error.h"
#include "clhair/hair_mesh.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = clhair::fuzz::writeInput(data, size, "input.hairmesh.json");
  try {
    const clhair::HairMesh m = clhair::loadHairMesh(path);
    clhair::validateHairMesh(m, path);  // loading validates already: must not throw now
  } catch (const clhair::Error&) {
  }
  return 0;
}
