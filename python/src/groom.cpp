// groom.cpp — strand grooms from NumPy arrays (no file in between) and strand files written
// from them (clhair.Groom, clhair.io.write_strands).
#include <memory>
#include <string>

#include <nanobind/stl/optional.h>
#include <nanobind/stl/shared_ptr.h>
#include <nanobind/stl/string.h>

#include "arrays.h"
#include "bindings.h"
#include "clhair/error.h"
#include "clhair/strand_groom.h"
#include "io/cyhair.h"
#include "io/ply_strands.h"
#include "io/usc_hair.h"

namespace clhair::py {

namespace {

std::shared_ptr<const StrandGroom> makeGroom(const nb::ndarray<>& points,
                                             const nb::ndarray<>& counts,
                                             const std::optional<nb::ndarray<>>& widths,
                                             const std::optional<nb::ndarray<>>& colors,
                                             const std::string& name) {
  const std::vector<float> p = floatValues(points, "points", 2, 3);
  const std::size_t n = p.size() / 3;
  const std::vector<std::int64_t> c = integerValues(counts, "counts", 2, 0xFFFFFFF0ll);
  std::uint64_t total = 0;
  for (std::int64_t k : c) total += static_cast<std::uint64_t>(k);
  if (total != n)
    throw Error("counts: add up to " + std::to_string(total) + " points, but points has " +
                std::to_string(n) + " rows (each strand owns counts[s] consecutive rows)");
  auto g = std::make_shared<StrandGroom>();
  g->name = name;
  g->pointCounts.assign(c.begin(), c.end());
  g->points.resize(n);
  for (std::size_t i = 0; i < n; ++i) g->points[i] = {p[3 * i], p[3 * i + 1], p[3 * i + 2]};
  if (widths) {
    std::vector<float> w = floatValues(*widths, "widths", 1, 0);
    if (w.size() != n)
      throw Error("widths: " + std::to_string(w.size()) + " values for " + std::to_string(n) +
                  " points (one width per point)");
    for (std::size_t i = 0; i < n; ++i)
      if (!(w[i] > 0.0f))
        throw Error("widths[" + std::to_string(i) + "] = " + std::to_string(w[i]) +
                    " is not positive");
    g->thickness = std::move(w);
  }
  if (colors) {
    std::vector<float> rgb = floatValues(*colors, "colors", 2, 3);
    if (rgb.size() != 3 * n)
      throw Error("colors: " + std::to_string(rgb.size() / 3) + " rows for " + std::to_string(n) +
                  " points (one linear rgb row per point)");
    g->colors.resize(n);
    for (std::size_t i = 0; i < n; ++i) g->colors[i] = {rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]};
  }
  validateStrandGroom(*g, "groom \"" + name + "\"");
  return g;
}

CyHair toCyHair(const StrandGroom& g) {
  CyHair h;
  h.segments.reserve(g.pointCounts.size());
  for (std::uint32_t c : g.pointCounts) h.segments.push_back(c - 1);
  h.points.reserve(3 * g.points.size());
  for (const glm::vec3& p : g.points) h.points.insert(h.points.end(), {p.x, p.y, p.z});
  h.thickness = g.thickness;
  for (const glm::vec3& c : g.colors) h.colors.insert(h.colors.end(), {c.x, c.y, c.z});
  h.info = "clhair python";
  return h;
}

std::string lowerExt(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string e = path.substr(dot);
  for (char& ch : e) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return e;
}

}  // namespace

void bindGroom(nb::module_& m) {
  nb::class_<GroomHandle>(m, "_GroomHandle", "A validated strand groom held in memory.")
      .def_prop_ro("strands", [](const GroomHandle& h) { return h.groom->pointCounts.size(); })
      .def_prop_ro("points", [](const GroomHandle& h) { return h.groom->points.size(); });
  m.def(
      "_make_groom",
      [](const nb::ndarray<>& points, const nb::ndarray<>& counts,
         const std::optional<nb::ndarray<>>& widths, const std::optional<nb::ndarray<>>& colors,
         const std::string& name) {
        return GroomHandle{makeGroom(points, counts, widths, colors, name)};
      },
      nb::arg("points"), nb::arg("counts"), nb::arg("widths").none(), nb::arg("colors").none(),
      nb::arg("name"));
  m.def(
      "_write_strands",
      [](const GroomHandle& h, const std::string& path) {
        const std::string ext = lowerExt(path);
        const CyHair hair = toCyHair(*h.groom);
        if (ext == ".hair")
          writeCyHair(hair, path);
        else if (ext == ".ply")
          writePlyStrands(hair, path);
        else if (ext == ".data")
          writeUscHair(hair, path);
        else
          throw Error(path + ": no strand-file writer for extension \"" + ext +
                      "\" (use .hair: cyHair, .ply: PLY, .data: USC-HairSalon)");
      },
      nb::arg("groom"), nb::arg("path"));
}

}  // namespace clhair::py
