// cyhair_write.cpp — writing cyHair `.hair` files (format in cyhair.h).
#include <cstring>

#include "clhair/error.h"
#include "io/cyhair.h"
#include "io/json_util.h"

namespace clhair {

namespace {

template <typename T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

}  // namespace

void writeCyHair(const CyHair& h, const std::string& path) {
  const std::size_t strands = h.segments.size();
  std::size_t points = 0;
  bool uniform = strands > 0;
  for (std::size_t i = 0; i < strands; ++i) {
    if (h.segments[i] > 0xFFFFu)
      throw Error(path + ": strand " + std::to_string(i) + " has more than 65535 segments");
    points += h.segments[i] + 1;
    uniform = uniform && h.segments[i] == h.segments[0];
  }
  if (h.points.size() != points * 3)
    throw Error(path + ": point array does not match the segment counts");
  if (!h.thickness.empty() && h.thickness.size() != points)
    throw Error(path + ": thickness array size mismatch");
  if (!h.transparency.empty() && h.transparency.size() != points)
    throw Error(path + ": transparency array size mismatch");
  if (!h.colors.empty() && h.colors.size() != points * 3)
    throw Error(path + ": colour array size mismatch");
  if (strands > 0xFFFFFFFFull || points > 0xFFFFFFFFull)
    throw Error(path + ": too many strands or points for cyHair");

  std::uint32_t flags = 2u;
  if (!uniform) flags |= 1u;
  if (!h.thickness.empty()) flags |= 4u;
  if (!h.transparency.empty()) flags |= 8u;
  if (!h.colors.empty()) flags |= 16u;

  std::string out;
  out.reserve(128 + points * 32);
  out.append("HAIR", 4);
  put(out, static_cast<std::uint32_t>(strands));
  put(out, static_cast<std::uint32_t>(points));
  put(out, flags);
  put(out, static_cast<std::uint32_t>(uniform ? h.segments[0] : 0u));
  put(out, h.defaultThickness);
  put(out, h.defaultTransparency);
  for (float c : h.defaultColor) put(out, c);
  char info[88] = {};
  std::strncpy(info, h.info.c_str(), sizeof(info) - 1);
  out.append(info, sizeof(info));
  if (flags & 1u)
    for (std::uint32_t s : h.segments) put(out, static_cast<std::uint16_t>(s));
  for (float v : h.points) put(out, v);
  for (float v : h.thickness) put(out, v);
  for (float v : h.transparency) put(out, v);
  for (float v : h.colors) put(out, v);
  writeTextAtomically(path, out);
}

}  // namespace clhair
