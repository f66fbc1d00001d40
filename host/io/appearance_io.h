// appearance_io.h — the "appearance" object shared by hair-mesh files and strand-file
// entries of a scene: melanin or colours, BSDF roughness/tilt/index, per-strand variation,
// fibre width and minimum hit diameter (docs/hair-mesh-format.md).
#pragma once

#include <nlohmann/json.hpp>

#include "clhair/hair_mesh.h"
#include "io/json_util.h"

namespace clhair {

// Reads `j` (the value of key "appearance" of `parent`) over the values already in `a`.
// `strandFile`: the entry names a strand file, which may also say "transparency" and
// "use_file_color", and whose colour keys, "strand_width" and "transparency" each turn off
// the file's own colours, thicknesses and transparencies.
void readAppearance(const JsonReader& parent, const nlohmann::json& j, AppearanceParams& a,
                    bool strandFile = false);

}  // namespace clhair
