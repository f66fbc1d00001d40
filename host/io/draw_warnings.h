// draw_warnings.h — why a groom with strands drew none, said after the frame.
//
// A groom can vanish for reasons the image does not show: it sits behind the camera, outside
// the view, nearer than the renderer's near limit, or it is smaller than a pixel (a strand file
// in the wrong units, a camera preset framing a groom too small to draw). viewWarnings
// (clhair/scene.h) warns about sizes before a render; drawWarnings looks at what a frame
// actually drew (FrameStats) and gives one line per groom instance that has strands but drew
// none, with the reason its bounds and the camera give, so an empty image is never silent.
#pragma once

#include <string>
#include <vector>

#include "clhair/renderer.h"
#include "clhair/scene.h"

namespace clhair {

// `scene` is the still frame rendered, `stats` its Frame::stats; `where` names the scene file.
std::vector<std::string> drawWarnings(const Scene& scene, const FrameStats& stats,
                                      const std::string& where);

}  // namespace clhair
