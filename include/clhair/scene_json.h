// scene_json.h — a scene given as JSON text rather than a file (the Python package builds
// scenes as dicts), with strand grooms that live in memory rather than in strand files.
//
// The text follows the scene-file schema (docs/scene-format.md) and is checked exactly as
// loadScene checks a file. A groom entry whose "strands_file" is one of the names in
// `memoryGrooms` takes that groom (its points, counts and per-point arrays) instead of
// reading a file; its "appearance", "lod", "scale", "up", "transform" and the other keys of
// a strand-file entry apply as they would to the file. Relative file names in the text are
// resolved against `baseDir`; `where` names the scene in error lines.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "clhair/scene.h"
#include "clhair/strand_groom.h"

namespace clhair {

using MemoryGrooms = std::map<std::string, std::shared_ptr<const StrandGroom>>;

Scene loadSceneJson(const std::string& text, const std::string& where, const std::string& baseDir,
                    const MemoryGrooms& memoryGrooms = {},
                    std::uint64_t maxStrandBytes = kDefaultStrandFileLimit);

}  // namespace clhair
