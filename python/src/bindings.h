// bindings.h — the pieces of the clhair._clhair module (one file per job) and the handles
// they share: a validated groom and a loaded scene, both immutable once made, so a renderer
// keeps their device forms across frames (its groom cache is keyed by their identity).
#pragma once

#include <memory>

#include <nanobind/nanobind.h>

#include "clhair/scene.h"
#include "clhair/strand_groom.h"

namespace clhair::py {

namespace nb = nanobind;

struct GroomHandle {
  std::shared_ptr<const StrandGroom> groom;
};

struct SceneHandle {
  std::shared_ptr<const Scene> scene;
};

void bindGroom(nb::module_& m);     // groom.cpp
void bindScene(nb::module_& m);     // scene.cpp
void bindRenderer(nb::module_& m);  // renderer.cpp
void bindImages(nb::module_& m);    // images.cpp

}  // namespace clhair::py
