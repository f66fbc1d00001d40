// view_notes.h — notes about how a scene will look, said before it renders
// (scene_view_notes.cpp).
#pragma once

#include <string>
#include <vector>

#include "clhair/scene.h"

namespace clhair {

// One line each, starting with `where` (the scene file): a strand-file groom (without
// "min_hit_diameter_px" or file thicknesses) whose fibres are under a quarter of a pixel wide
// and whose hair covers under 5 % of its screen box (faint_groom.h), so that it draws faint
// (the line names "min_hit_diameter_px"), unless `widensFaint` (the render's filter runs and
// draws it at least a pixel wide itself); a scene with grooms and neither lights nor an
// environment.
std::vector<std::string> viewNotes(const Scene& scene, const std::string& where, bool widensFaint);

}  // namespace clhair
