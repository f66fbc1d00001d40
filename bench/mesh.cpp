// mesh.cpp — the benchmark's mesh section (clhair_bench --only mesh):
// The head as the analytic sphere vs a ~50k-triangle OBJ-style mesh of the same sphere (generated
// here): frame time and the opaque + mesh stages' times.
#include "harness.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "clhair/triangle_mesh.h"

namespace clhair::bench {

void runMesh(Run& r) {
  // groom1's head sphere (radius 0.093) against a latitude/longitude mesh of the same
  // sphere with 158 rings of 160 segments (50 240 triangles, a decimated head scan's
  // size) at close range, where the head covers the most pixels
  TriangleMesh head;
  head.name = "sphere50k";
  constexpr int kRings = 158, kSegments = 160;
  const glm::vec3 c = r.scenes[0].spheres.at(0).center;
  const float radius = r.scenes[0].spheres.at(0).radius;
  head.positions.push_back(c + glm::vec3(0, radius, 0));
  for (int i = 1; i < kRings; ++i)
    for (int j = 0; j < kSegments; ++j) {
      const float th = 3.14159265f * i / kRings, ph = 6.28318531f * j / kSegments;
      head.positions.push_back(c + radius * glm::vec3(std::sin(th) * std::cos(ph), std::cos(th),
                                                      std::sin(th) * std::sin(ph)));
    }
  head.positions.push_back(c - glm::vec3(0, radius, 0));
  const auto ring = [&](int i, int j) {
    return static_cast<std::uint32_t>(1 + (i - 1) * kSegments + j % kSegments);
  };
  const auto bottom = static_cast<std::uint32_t>(head.positions.size() - 1);
  for (int j = 0; j < kSegments; ++j) {
    head.indices.insert(head.indices.end(), {0u, ring(1, j + 1), ring(1, j)});
    head.indices.insert(head.indices.end(), {bottom, ring(kRings - 1, j), ring(kRings - 1, j + 1)});
  }
  for (int i = 1; i < kRings - 1; ++i)
    for (int j = 0; j < kSegments; ++j)
      head.indices.insert(head.indices.end(), {ring(i, j), ring(i, j + 1), ring(i + 1, j + 1),
                                               ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
  const std::size_t triangles = head.indices.size() / 3;
  auto headMesh = std::make_shared<const TriangleMesh>(std::move(head));
  r.md << "\n## Head as a triangle mesh (" << r.groomNames[0] << ", " << r.opt.width << "x"
       << r.opt.height << ", close, " << triangles
       << " triangles)\n\n| head | frame ms | opaque ms | mesh ms | opaque + mesh share of the "
          "frame |\n"
       << "|---|---|---|---|---|\n";
  double sphereOpaque = 0.0, sphereShare = 0.0;
  for (int asMesh = 0; asMesh < 2; ++asMesh) {
    Scene s = framed(r.scenes[0], CameraPreset::Close, r.opt.width, r.opt.height);
    if (asMesh) {
      MeshInstance mi;
      mi.name = headMesh->name;
      mi.mesh = headMesh;
      mi.color = s.spheres[0].color;
      s.spheres.clear();
      s.meshes.push_back(mi);
    }
    Measured m = r.b.measure(s, RenderOptions{}, false);
    const double opaqueMs = stageMedian(m, "opaque") + stageMedian(m, "mesh");
    const double share = opaqueMs / std::max(m.total.median, 1e-9);
    const char* name = asMesh ? "mesh" : "sphere";
    r.md << "| " << name << " | " << fmt(m.total.median) << " | " << fmt(stageMedian(m, "opaque"))
         << " | " << fmt(stageMedian(m, "mesh")) << " | " << fmt(100.0 * share, 1) << " % |\n";
    r.report["mesh"][name] = measuredJson(m);
    r.report["mesh"][name]["opaque_and_mesh_ms"] = opaqueMs;
    std::fprintf(stderr, "mesh section, %s head: frame %.1f ms, opaque %.2f ms, mesh %.2f ms\n",
                 name, m.total.median, stageMedian(m, "opaque"), stageMedian(m, "mesh"));
    if (!asMesh) {
      sphereOpaque = opaqueMs;
      sphereShare = share;
    } else {
      r.report["mesh"]["cost_vs_sphere"] = opaqueMs / std::max(sphereOpaque, 1e-9);
      r.md << "\nThe mesh head's opaque work is " << fmt(opaqueMs / std::max(sphereOpaque, 1e-9))
           << "x the sphere's (" << fmt(100.0 * share, 1) << " % against "
           << fmt(100.0 * sphereShare, 1) << " % of the frame; target: at most 2x).\n";
    }
  }
}

}  // namespace clhair::bench
