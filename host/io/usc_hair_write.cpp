// usc_hair_write.cpp — writing USC-HairSalon `.data` files (format in usc_hair.h).
#include <cstdint>
#include <cstring>
#include <limits>

#include "clhair/error.h"
#include "io/binary_file.h"
#include "io/json_util.h"
#include "io/usc_hair.h"

namespace clhair {

void writeUscHair(const CyHair& hair, const std::string& path) {
  constexpr std::uint64_t kMaxCount =
      static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max());
  std::uint64_t points = 0;
  for (std::uint32_t s : hair.segments) {
    if (s + std::uint64_t(1) > kMaxCount)
      throw Error(path + ": a strand has too many points for USC-HairSalon");
    points += s + std::uint64_t(1);
  }
  if (hair.segments.size() > kMaxCount) throw Error(path + ": too many strands for USC-HairSalon");
  if (hair.points.size() != points * 3)
    throw Error(path + ": point array does not match the segment counts");
  std::string out;
  out.reserve(4 + 4 * hair.segments.size() + 12 * points);
  appendU32(out, static_cast<std::uint32_t>(hair.segments.size()));
  std::size_t at = 0;
  for (std::uint32_t s : hair.segments) {
    appendU32(out, s + 1u);
    for (std::uint64_t k = 0; k < 3 * (s + std::uint64_t(1)); ++k, ++at) {
      std::uint32_t bits;
      std::memcpy(&bits, &hair.points[at], sizeof(bits));
      appendU32(out, bits);
    }
  }
  writeTextAtomically(path, out);
}

}  // namespace clhair
