/* labels.cl — the labels hair models learn from, computed from a frame's tangent and hair
 * alpha layers (Frame::aovs), one work-item per pixel (clhair/labels.h):
 * - the strand's direction in the image: the world tangent turned into view space and
 *   differentiated through the pinhole projection at the pixel's own ray
 *   (x = cx + fx X / Z, y = cy - fy Y / Z): d(X/Z) = (tX - a tZ) / Z, d(Y/Z) = (tY - b tZ) / Z
 *   with (a, b) = (X/Z, Y/Z) of the pixel centre; unit length, x right, y up;
 * - its angle modulo pi, counter-clockwise from +x (NeuralHaircut's orientation map), and
 *   the confidence: the hair alpha times the sine of the angle between the tangent and the
 *   pixel's view ray (1 across the view, 0 pointing at the camera);
 * 0 in all four where the pixel has no strand (a zero tangent). Output per pixel:
 * (angle, confidence, direction x, direction y). The host reference is python/clhair/labels.py
 * and tests/test_labels.cpp. */
#include "clhair/gpu_types.h"

#pragma OPENCL FP_CONTRACT OFF

__kernel void hair_labels(__global const ClhViewGpu* view_g, uint width, uint pixels,
                          __global const float* tangent_g, __global const float* alpha_g,
                          __global float4* out_g) {
  const size_t p = get_global_id(0);
  if (p >= pixels || width == 0u) return;
  const float tx = tangent_g[3 * p], ty = tangent_g[3 * p + 1], tz = tangent_g[3 * p + 2];
  out_g[p] = (float4)(0.0f);
  if (tx == 0.0f && ty == 0.0f && tz == 0.0f) return;
  __global const float* m = view_g->world_to_view;
  const float vx = m[0] * tx + m[1] * ty + m[2] * tz;
  const float vy = m[4] * tx + m[5] * ty + m[6] * tz;
  const float vz = m[8] * tx + m[9] * ty + m[10] * tz;
  const float px = (float)(p % width), py = (float)(p / width);
  const float a = (px + 0.5f - view_g->cx) / view_g->fx;
  const float b = -(py + 0.5f - view_g->cy) / view_g->fy;
  const float dx = vx - a * vz, dy = vy - b * vz;
  const float len = sqrt(dx * dx + dy * dy);
  if (!(len > 1e-12f)) return;
  const float ux = dx / len, uy = dy / len;
  /* the sine between the tangent and the ray (a, b, 1) */
  const float rl = sqrt(a * a + b * b + 1.0f);
  const float rx = a / rl, ry = b / rl, rz = 1.0f / rl;
  const float cx = vy * rz - vz * ry, cy = vz * rx - vx * rz, cz = vx * ry - vy * rx;
  const float tn = sqrt(vx * vx + vy * vy + vz * vz);
  const float sine = clamp(sqrt(cx * cx + cy * cy + cz * cz) / tn, 0.0f, 1.0f);
  float angle = atan2(uy, ux);
  if (angle < 0.0f) angle += M_PI_F;
  if (angle >= M_PI_F) angle -= M_PI_F;
  if (!(angle >= 0.0f && angle < M_PI_F)) angle = 0.0f;
  const float alpha = clamp(alpha_g[p], 0.0f, 1.0f);
  out_g[p] = (float4)(angle, alpha * sine, ux, uy);
}
