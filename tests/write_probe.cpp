// write_probe.cpp — a test helper: writes one small file of one kind through clhair's own
// writer for it, so the fault-injection tests (test_faults.cpp) can run every writer in a child
// process under a full file system, a read-only folder or the fault shim (fault_shim.c),
// without rendering anything.
//
//   clhair_write_probe KIND PATH [KIND PATH ...]
//
// KIND: png, exr, jpg, hdr, tif (writeImage of a 40x30 gradient), aov (writeChannels), hair
// (writeCyHair), data (writeUscHair), tfx (writeTressFx), ply (writePlyStrands), visibility
// (writeVisibility),
// hairmesh (saveHairMesh of the tiny preset), cage (saveCageAnimation), bytes
// (writeFileAtomically of 64 KiB). The files are written in order, each independently; every
// failed one prints one line "clhair: error: ..." (as the command does). Exit code 0 when all
// were written, else 1.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "clhair/animation.h"
#include "clhair/aov.h"
#include "clhair/error.h"
#include "clhair/hair_mesh.h"
#include "clhair/image.h"
#include "clhair/visibility.h"
#include "clhair/visibility_sh.h"
#include "groom/presets.h"
#include "io/cyhair.h"
#include "io/ply_strands.h"
#include "io/safe_write.h"
#include "io/tressfx.h"
#include "io/usc_hair.h"

namespace {

using namespace clhair;

Image gradient() {
  Image img;
  img.width = 40;
  img.height = 30;
  img.rgba.resize(static_cast<std::size_t>(img.width) * img.height * 4);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      float* p = img.pixel(x, y);
      p[0] = x / 39.0f;
      p[1] = y / 29.0f;
      p[2] = 0.25f;
      p[3] = 1.0f;
    }
  return img;
}

CyHair strands(std::uint32_t points) {
  CyHair h;
  for (int s = 0; s < 50; ++s) {
    h.segments.push_back(points - 1);
    for (std::uint32_t k = 0; k < points; ++k)
      h.points.insert(h.points.end(), {0.001f * s, 0.01f * k, 0.0f});
  }
  return h;
}

void write(const std::string& kind, const std::string& path) {
  if (kind == "png" || kind == "exr" || kind == "jpg" || kind == "hdr" || kind == "tif") {
    writeImage(gradient(), path);
  } else if (kind == "aov") {
    const Image img = gradient();
    std::vector<ImageChannel> channels;
    for (int c = 0; c < 4; ++c) {
      ImageChannel ch{std::string(1, "RGBA"[c]), {}, true};
      for (std::size_t p = 0; p < img.rgba.size() / 4; ++p)
        ch.values.push_back(img.rgba[p * 4 + c]);
      channels.push_back(ch);
    }
    channels.push_back({"Z", std::vector<float>(img.rgba.size() / 4, 2.0f), false});
    writeChannels(channels, img.width, img.height, path);
  } else if (kind == "hair") {
    writeCyHair(strands(8), path);
  } else if (kind == "data") {
    writeUscHair(strands(8), path);
  } else if (kind == "tfx") {
    TressFxHair t;
    t.hair = strands(8);
    writeTressFx(t, path);
  } else if (kind == "ply") {
    writePlyStrands(strands(8), path);
  } else if (kind == "visibility") {
    VisibilityBake b;
    b.strands = 50;
    b.raysPerPoint = 1;
    b.pointsPerCell = 1;
    b.sh.assign(std::size_t(CLH_VIS_CELLS) * CLH_VIS_COEFFS, 0.5f);
    writeVisibility(b, path);
  } else if (kind == "hairmesh") {
    saveHairMesh(makeGroomPreset("tiny"), path);
  } else if (kind == "cage") {
    CageAnimation c;
    c.frames = 2;
    c.vertices = 100;
    c.positions.assign(200, glm::vec3(0.5f, 1.0f, -0.25f));
    saveCageAnimation(c, path);
  } else if (kind == "bytes") {
    writeFileAtomically(path, std::string(64 << 10, 'x'));
  } else {
    throw Error("unknown kind \"" + kind + "\"");
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3 || argc % 2 != 1) {
    std::fprintf(stderr, "usage: clhair_write_probe KIND PATH [KIND PATH ...]\n");
    return 2;
  }
  int failed = 0;
  for (int i = 1; i + 1 < argc; i += 2) {
    try {
      write(argv[i], argv[i + 1]);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "clhair: error: %s\n", e.what());
      ++failed;
    }
  }
  return failed ? 1 : 0;
}
