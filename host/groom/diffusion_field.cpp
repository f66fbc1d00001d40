// diffusion_field.cpp — see diffusion_field.h.
#include "groom/diffusion_field.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/geometric.hpp>

namespace clhair {

namespace {

constexpr float kAoFixed = 4096.0f;  // kernels/ao.cl, AO_FIXED
constexpr double kPi = 3.14159265358979323846;
// The groom's surface lets the scattered light out at this share of the rate of an isotropic
// medium's (Marshak's boundary condition, net flux phi / 2 through an open face). Measured
// against the path reference (DESIGN.md, "Hair the colour of hair"; the light strand file's
// mean ΔE over close / mid / far, draft and good): 0.08 10.9 (red overshoots), 0.15 4.4,
// 0.2 4.2, 0.3 6.6. Fibres lie along the groom's surface and scatter light on cones about
// their axes, so light keeps its direction along the hair and reaches the surface less
// often than in an isotropic medium; the head under the hair reflects part of what reaches
// it. Both are left out of the diffusion itself; this constant stands for them.
constexpr double kLeak = 0.2;
// Over-relaxation of the Gauss-Seidel sweeps, and the relative change below which they stop.
constexpr float kOmega = 1.8f;
constexpr double kTolerance = 1e-4;

}  // namespace

std::vector<glm::vec3> diffuseGroomLight(const AoDensity& d, glm::vec3 albedo,
                                         const std::vector<DiffusionLight>& lights,
                                         float worldPerObject, float g, int iterations) {
  const int nx = static_cast<int>(d.grid.dims.s[0]), ny = static_cast<int>(d.grid.dims.s[1]),
            nz = static_cast<int>(d.grid.dims.s[2]);
  const std::size_t n = static_cast<std::size_t>(nx) * ny * nz;
  std::vector<glm::vec3> out(n, glm::vec3(0.0f));
  if (n == 0 || d.density.size() != n || lights.empty() || !(worldPerObject > 0.0f) ||
      !(d.grid.lo.s[3] > 0.0f))
    return out;
  const float h = d.grid.lo.s[3];  // object units
  const glm::vec3 lo(d.grid.lo.s[0], d.grid.lo.s[1], d.grid.lo.s[2]);
  // extinction per world unit; an opaque voxel is at least 16 optical depths per half voxel
  const float hw = h * worldPerObject;
  std::vector<float> sigma(n);
  std::vector<char> solid(n), hair(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float s = static_cast<float>(d.density[i]) / kAoFixed / worldPerObject;
    solid[i] = s * hw >= 30.0f;
    hair[i] = !solid[i] && s * hw > 0.05f;  // sparser voxels count as empty
    sigma[i] = solid[i] ? 0.0f : s;
  }
  auto index = [&](int x, int y, int z) { return (std::size_t(z) * ny + y) * nx + x; };

  // uncollided light at every hair voxel: march toward each light in half-voxel steps
  std::vector<glm::vec3> phi0(n, glm::vec3(0.0f));
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const std::size_t i = index(x, y, z);
        if (!hair[i]) continue;
        const glm::vec3 p = lo + (glm::vec3(x, y, z) + 0.5f) * h;
        for (const DiffusionLight& l : lights) {
          glm::vec3 dir = l.point ? l.at - p : l.at;
          const float dist = glm::length(dir);
          if (!(dist > 0.0f)) continue;
          dir /= dist;
          const float reach = l.point ? dist : 1e30f;
          double tau = 0.0;
          bool blocked = false;
          for (float t = 0.25f * h; t < reach; t += 0.5f * h) {  // mid-points of half voxels
            const glm::vec3 q = (p + dir * t - lo) / h;
            const int qx = static_cast<int>(std::floor(q.x)),
                      qy = static_cast<int>(std::floor(q.y)),
                      qz = static_cast<int>(std::floor(q.z));
            if (qx < 0 || qy < 0 || qz < 0 || qx >= nx || qy >= ny || qz >= nz) break;
            const std::size_t j = index(qx, qy, qz);
            if (solid[j]) {
              blocked = true;
              break;
            }
            tau += sigma[j] * 0.5 * hw;
            if (tau > 40.0) break;
          }
          if (blocked || tau > 40.0) continue;
          const float falloff =
              l.point ? 1.0f / std::max(dist * dist * worldPerObject * worldPerObject, 1e-8f)
                      : 1.0f;
          phi0[i] += l.radiance * (falloff * static_cast<float>(std::exp(-tau)));
        }
      }

  // the diffusion of what the fibres scatter, per channel, by Gauss-Seidel with
  // over-relaxation; phi = 0 in the empty and opaque voxels around the hair
  for (int c = 0; c < 3; ++c) {
    const float a = std::clamp(albedo[c], 0.0f, 0.995f);
    std::vector<float> D(n, 0.0f), absorb(n, 0.0f), src(n, 0.0f), phi(n, 0.0f);
    for (std::size_t i = 0; i < n; ++i) {
      if (!hair[i]) continue;
      const float ss = a * sigma[i], sa = (1.0f - a) * sigma[i];
      D[i] = 1.0f / (3.0f * (sa + ss * (1.0f - g)));
      absorb[i] = sa;
      src[i] = ss * phi0[i][c];
    }
    const float inv_h2 = 1.0f / (hw * hw);
    for (int it = 0; it < iterations; ++it) {
      double change = 0.0, level = 0.0;
      for (int z = 0; z < nz; ++z)
        for (int y = 0; y < ny; ++y)
          for (int x = 0; x < nx; ++x) {
            const std::size_t i = index(x, y, z);
            if (!hair[i]) continue;
            double num = src[i], den = absorb[i];
            const std::array<std::array<int, 3>, 6> nb = {{{x - 1, y, z},
                                                           {x + 1, y, z},
                                                           {x, y - 1, z},
                                                           {x, y + 1, z},
                                                           {x, y, z - 1},
                                                           {x, y, z + 1}}};
            for (const auto& q : nb) {
              const bool inside =
                  q[0] >= 0 && q[1] >= 0 && q[2] >= 0 && q[0] < nx && q[1] < ny && q[2] < nz;
              const std::size_t j = inside ? index(q[0], q[1], q[2]) : i;
              if (inside && hair[j]) {
                const float df = 2.0f * D[i] * D[j] / (D[i] + D[j]);
                num += df * inv_h2 * phi[j];
                den += df * inv_h2;
              } else {
                // light leaving through the face (empty or opaque beyond): a half voxel of
                // diffusion in series with the surface's outgoing flux phi / 2 (Marshak)
                den += kLeak / (hw * (0.5 * hw / D[i] + 2.0));
              }
            }
            const float next = static_cast<float>(num / std::max(den, 1e-30));
            const float was = phi[i];
            phi[i] = std::max(0.0f, was + kOmega * (next - was));
            change += std::fabs(phi[i] - was);
            level += phi[i];
          }
      if (change <= kTolerance * level) break;
    }
    for (std::size_t i = 0; i < n; ++i) out[i][c] = static_cast<float>(a * phi[i] / (4.0 * kPi));
  }
  // voxels beside the hair take the mean of their hair neighbours, so that a fibre near the
  // groom's surface, looked up trilinearly, does not blend with the zero outside
  std::vector<glm::vec3> grown = out;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const std::size_t i = index(x, y, z);
        if (hair[i]) continue;
        glm::vec3 sum(0.0f);
        int count = 0;
        for (int dz = -1; dz <= 1; ++dz)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const int qx = x + dx, qy = y + dy, qz = z + dz;
              if (qx < 0 || qy < 0 || qz < 0 || qx >= nx || qy >= ny || qz >= nz) continue;
              const std::size_t j = index(qx, qy, qz);
              if (!hair[j]) continue;
              sum += out[j];
              ++count;
            }
        if (count > 0) grown[i] = sum / static_cast<float>(count);
      }
  return grown;
}

}  // namespace clhair
