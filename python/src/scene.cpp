// scene.cpp — scenes from a file or from JSON text with grooms held in memory
// (clhair/scene_json.h), read once and rendered any number of times.
#include <map>
#include <string>

#include <nanobind/stl/map.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "bindings.h"
#include "clhair/scene_json.h"

namespace clhair::py {

void bindScene(nb::module_& m) {
  nb::class_<SceneHandle>(m, "_SceneHandle", "A loaded scene.")
      .def_prop_ro("width", [](const SceneHandle& s) { return s.scene->width; })
      .def_prop_ro("height", [](const SceneHandle& s) { return s.scene->height; })
      .def_prop_ro("grooms", [](const SceneHandle& s) { return s.scene->grooms.size(); })
      .def_prop_ro("warnings", [](const SceneHandle& s) { return s.scene->warnings; })
      .def_prop_ro("notes", [](const SceneHandle& s) { return s.scene->notes; });
  m.def(
      "_load_scene",
      [](const std::string& path) {
        nb::gil_scoped_release unlocked;
        return SceneHandle{std::make_shared<const Scene>(loadScene(path))};
      },
      nb::arg("path"));
  m.def(
      "_load_scene_json",
      [](const std::string& text, const std::string& where, const std::string& baseDir,
         const std::map<std::string, GroomHandle>& grooms, int width, int height) {
        MemoryGrooms memory;
        for (const auto& [name, h] : grooms) memory[name] = h.groom;
        nb::gil_scoped_release unlocked;
        Scene s = loadSceneJson(text, where, baseDir, memory);
        if (width > 0) s.width = width;
        if (height > 0) s.height = height;
        return SceneHandle{std::make_shared<const Scene>(std::move(s))};
      },
      nb::arg("text"), nb::arg("where"), nb::arg("base_dir"), nb::arg("grooms"),
      nb::arg("width") = 0, nb::arg("height") = 0);
}

}  // namespace clhair::py
