// view_math.cpp — see view_math.h.
#include "stages/view_math.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

namespace clhair {

void store4(float* dst, const glm::vec3& v, float w) {
  dst[0] = v.x;
  dst[1] = v.y;
  dst[2] = v.z;
  dst[3] = w;
}

void storeMat34(float* dst, const glm::mat4& m) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) dst[r * 4 + c] = m[c][r];
}

glm::mat4 worldToView(const Camera& cam) {
  glm::vec3 f = glm::normalize(cam.target - cam.position);
  glm::vec3 r = glm::normalize(glm::cross(f, cam.up));
  glm::vec3 u = glm::cross(r, f);
  glm::mat4 m(1.0f);
  for (int c = 0; c < 3; ++c) {
    m[c][0] = r[c];
    m[c][1] = u[c];
    m[c][2] = f[c];
  }
  m[3][0] = -glm::dot(r, cam.position);
  m[3][1] = -glm::dot(u, cam.position);
  m[3][2] = -glm::dot(f, cam.position);
  return m;
}

FaintView faintView(const gpu::ClhViewGpu& v) {
  FaintView f;
  f.fx = v.fx;
  f.fy = v.fy;
  f.cx = v.cx;
  f.cy = v.cy;
  f.width = v.width;
  f.height = v.height;
  return f;
}

gpu::ClhViewGpu makeView(const Camera& cam, int width, int height) {
  gpu::ClhViewGpu v;
  std::memset(&v, 0, sizeof(v));
  glm::mat4 w2v = worldToView(cam);
  storeMat34(v.world_to_view, w2v);
  storeMat34(v.view_to_world, glm::inverse(w2v));
  float fy = 0.5f * static_cast<float>(height) / std::tan(glm::radians(cam.fovYDegrees) * 0.5f);
  v.fx = fy;
  v.fy = fy;
  v.cx = 0.5f * static_cast<float>(width);
  v.cy = 0.5f * static_cast<float>(height);
  v.width = static_cast<gpu::clh_u32>(width);
  v.height = static_cast<gpu::clh_u32>(height);
  v.samples = 1;
  store4(v.eye, cam.position, 1.0f);
  return v;
}

bool depthRange(const glm::vec3& lo, const glm::vec3& hi, const glm::mat4& objToView, float& nearZ,
                float& farZ) {
  float zmin = 1e30f, zmax = -1e30f;
  for (int c = 0; c < 8; ++c) {
    glm::vec3 corner((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
    float z = (objToView * glm::vec4(corner, 1.0f)).z;
    zmin = std::min(zmin, z);
    zmax = std::max(zmax, z);
  }
  if (zmax <= 1e-4f) return false;
  nearZ = std::max(zmin, 1e-4f);
  farZ = std::max(zmax, nearZ * 1.0001f + 1e-6f);
  return true;
}

PixelRect screenBox(const glm::vec3& lo, const glm::vec3& hi, const glm::mat4& objToView,
                    const gpu::ClhViewGpu& view, int margin) {
  const int width = static_cast<int>(view.width), height = static_cast<int>(view.height);
  const PixelRect whole{0, 0, width, height};
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  for (int c = 0; c < 8; ++c) {
    const glm::vec3 corner((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
    const glm::vec4 v = objToView * glm::vec4(corner, 1.0f);
    if (!(v.z >= kScreenBoxNearZ) || !std::isfinite(v.x) || !std::isfinite(v.y) ||
        !std::isfinite(v.z))
      return whole;
    const double sx = double(view.cx) + double(view.fx) * double(v.x) / double(v.z);
    const double sy = double(view.cy) - double(view.fy) * double(v.y) / double(v.z);
    xmin = std::min(xmin, sx);
    xmax = std::max(xmax, sx);
    ymin = std::min(ymin, sy);
    ymax = std::max(ymax, sy);
  }
  // the pixel holding coordinate s is floor(s); far outside the image only the side matters
  auto pixel = [](double s) {
    return static_cast<long long>(std::floor(std::clamp(s, -1e9, 1e9)));
  };
  const long long x0 = pixel(xmin) - margin, x1 = pixel(xmax) + 1 + margin;
  const long long y0 = pixel(ymin) - margin, y1 = pixel(ymax) + 1 + margin;
  auto side = [](long long v, int hiSide) {
    return static_cast<int>(std::max<long long>(0, std::min<long long>(hiSide, v)));
  };
  return {side(x0, width), side(y0, height), side(x1, width), side(y1, height)};
}

}  // namespace clhair
