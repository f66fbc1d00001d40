// image_codec_loader.h — the command's image codec, loaded on first use (image_codec_loader.cpp,
// io/image_codec.h).
#pragma once

namespace clhair {

// Loads the image codec now, if not yet: a command that will write images calls it before
// any work, so a missing codec module is one error line at once, not after the render.
// Throws clhair::Error when it cannot be loaded.
void loadImageCodec();

}  // namespace clhair
