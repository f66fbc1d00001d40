// png_check.cpp — see png_check.h (the PNG specification, ISO/IEC 15948, chunk layout and
// Adam7 interlacing).
#include "io/png_check.h"

#include <zlib.h>

#include <array>
#include <cstring>
#include <vector>

#include "clhair/error.h"

namespace clhair {

namespace {

constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
constexpr std::uint32_t kMaxChunk = 0x7FFFFFFFu;

std::uint32_t loadBe32(const unsigned char* p) {
  return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 |
         std::uint32_t(p[3]);
}

// Bytes of one row of `width` pixels at `bitsPerPixel`, without its filter byte.
std::uint64_t rowBytes(std::uint64_t width, std::uint32_t bitsPerPixel) {
  return (width * bitsPerPixel + 7) / 8;
}

// The rows of the image data: one per row (one pass), or per row of each Adam7 pass.
struct RowPlan {
  std::vector<std::pair<std::uint64_t, std::uint64_t>> runs;  // (rows, bytes per row with filter)
  std::uint64_t total = 0;
};

RowPlan planRows(std::uint32_t width, std::uint32_t height, std::uint32_t bpp, bool interlaced) {
  RowPlan plan;
  auto add = [&](std::uint64_t w, std::uint64_t h) {
    if (w == 0 || h == 0) return;
    const std::uint64_t bytes = 1 + rowBytes(w, bpp);
    plan.runs.push_back({h, bytes});
    plan.total += h * bytes;
  };
  if (!interlaced) {
    add(width, height);
    return plan;
  }
  // Adam7: (x start, y start, x step, y step) of the seven passes
  constexpr int kPass[7][4] = {{0, 0, 8, 8}, {4, 0, 8, 8}, {0, 4, 4, 8}, {2, 0, 4, 4},
                               {0, 2, 2, 4}, {1, 0, 2, 2}, {0, 1, 1, 2}};
  for (const auto& p : kPass) {
    const std::uint64_t w = width > std::uint32_t(p[0]) ? (width - p[0] + p[2] - 1) / p[2] : 0;
    const std::uint64_t h = height > std::uint32_t(p[1]) ? (height - p[1] + p[3] - 1) / p[3] : 0;
    add(w, h);
  }
  return plan;
}

}  // namespace

bool looksLikePng(const std::string& bytes) {
  return bytes.size() >= sizeof(kSignature) &&
         std::memcmp(bytes.data(), kSignature, sizeof(kSignature)) == 0;
}

void checkPng(const std::string& bytes, const std::string& path, std::uint64_t maxPixels) {
  const std::string where = path + ": damaged PNG file: ";
  if (!looksLikePng(bytes)) throw Error(where + "no PNG signature");
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const std::size_t size = bytes.size();

  std::uint32_t width = 0, height = 0, bpp = 0;
  bool interlaced = false, havePalette = false, seenIdat = false, idatEnded = false,
       seenEnd = false;
  int colourType = -1;
  std::vector<std::pair<std::size_t, std::size_t>> idat;  // (offset, length) of each IDAT
  std::size_t at = sizeof(kSignature);
  for (int index = 0; !seenEnd; ++index) {
    if (size - at < 12)
      throw Error(where + "ends at byte " + std::to_string(size) + " inside chunk " +
                  std::to_string(index) + " (no IEND chunk)");
    const std::uint32_t length = loadBe32(data + at);
    char type[5] = {};
    std::memcpy(type, data + at + 4, 4);
    const std::string name(type);
    for (char c : name)
      if (!((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z')))
        throw Error(where + "chunk " + std::to_string(index) + " at byte " + std::to_string(at) +
                    " has no valid type");
    if (length > kMaxChunk || length > size - at - 12)
      throw Error(where + "chunk " + std::to_string(index) + " (" + name + ") declares " +
                  std::to_string(length) + " bytes, the file ends " +
                  std::to_string(size - at - 12) + " bytes later");
    const unsigned char* body = data + at + 8;
    const std::uint32_t crc = static_cast<std::uint32_t>(
        ::crc32(::crc32(0L, Z_NULL, 0), data + at + 4, static_cast<uInt>(length + 4)));
    if (crc != loadBe32(body + length))
      throw Error(where + "chunk " + std::to_string(index) + " (" + name + ") fails its CRC");
    if (index == 0 && name != "IHDR") throw Error(where + "the first chunk is not IHDR");
    if (name == "IHDR") {
      if (index != 0 || length != 13) throw Error(where + "a misplaced or malformed IHDR chunk");
      width = loadBe32(body);
      height = loadBe32(body + 4);
      const int depth = body[8];
      colourType = body[9];
      if (width == 0 || height == 0 || width > kMaxChunk || height > kMaxChunk)
        throw Error(where + "image size " + std::to_string(width) + "x" + std::to_string(height) +
                    " is invalid");
      static const std::array<std::pair<int, int>, 5> kChannels = {
          {{0, 1}, {2, 3}, {3, 1}, {4, 2}, {6, 4}}};
      int channels = 0;
      for (const auto& [t, n] : kChannels)
        if (t == colourType) channels = n;
      const bool depthOk =
          (colourType == 0 &&
           (depth == 1 || depth == 2 || depth == 4 || depth == 8 || depth == 16)) ||
          (colourType == 3 && (depth == 1 || depth == 2 || depth == 4 || depth == 8)) ||
          ((colourType == 2 || colourType == 4 || colourType == 6) && (depth == 8 || depth == 16));
      if (channels == 0 || !depthOk)
        throw Error(where + "colour type " + std::to_string(colourType) + " with " +
                    std::to_string(depth) + "-bit samples is invalid");
      if (body[10] != 0 || body[11] != 0 || body[12] > 1)
        throw Error(where + "unknown compression, filter or interlace method");
      bpp = static_cast<std::uint32_t>(channels * depth);
      interlaced = body[12] == 1;
      if (std::uint64_t(width) * height > maxPixels)
        throw Error(path + ": image size " + std::to_string(width) + "x" + std::to_string(height) +
                    " is over the limit of " + std::to_string(maxPixels) + " pixels");
    } else if (name == "PLTE") {
      if (seenIdat) throw Error(where + "PLTE after the image data");
      if (length == 0 || length % 3 != 0 || length > 768)
        throw Error(where + "a palette of " + std::to_string(length) + " bytes");
      havePalette = true;
    } else if (name == "IDAT") {
      if (idatEnded) throw Error(where + "IDAT chunks are not consecutive");
      seenIdat = true;
      idat.push_back({at + 8, length});
    } else if (name == "IEND") {
      seenEnd = true;
    } else if (name[0] >= 'A' && name[0] <= 'Z') {
      throw Error(where + "unknown critical chunk " + name);
    }
    if (seenIdat && name != "IDAT") idatEnded = true;
    at += 12 + std::size_t(length);
  }
  if (!seenIdat) throw Error(where + "no image data (IDAT)");
  if (colourType == 3 && !havePalette) throw Error(where + "a palette image without PLTE");

  // The image data: inflate chunk by chunk into a small buffer, checking each row's filter byte.
  const RowPlan plan = planRows(width, height, bpp, interlaced);
  z_stream z{};
  if (::inflateInit(&z) != Z_OK) throw Error(path + ": cannot start zlib to check the PNG data");
  std::vector<unsigned char> out(1 << 16);
  std::uint64_t produced = 0;
  std::size_t run = 0;
  std::uint64_t rowInRun = 0, posInRow = 0;
  int status = Z_OK;
  std::string fault;
  for (std::size_t k = 0; k < idat.size() && status != Z_STREAM_END && fault.empty(); ++k) {
    z.next_in = const_cast<unsigned char*>(data + idat[k].first);
    z.avail_in = static_cast<uInt>(idat[k].second);
    while (z.avail_in > 0 && status != Z_STREAM_END && fault.empty()) {
      z.next_out = out.data();
      z.avail_out = static_cast<uInt>(out.size());
      status = ::inflate(&z, Z_NO_FLUSH);
      if (status != Z_OK && status != Z_STREAM_END && status != Z_BUF_ERROR) {
        fault =
            std::string("the image data does not inflate (") + (z.msg ? z.msg : "zlib error") + ")";
        break;
      }
      const std::size_t got = out.size() - z.avail_out;
      if (produced + got > plan.total) {
        fault = "the image data holds more than the " + std::to_string(plan.total) +
                " bytes its header declares";
        break;
      }
      // walk the rows: the byte at the start of each row is its filter type, 0..4
      for (std::size_t i = 0; i < got;) {
        if (posInRow == 0 && out[i] > 4) {
          fault = "row filter " + std::to_string(out[i]) + " at image data byte " +
                  std::to_string(produced + i);
          break;
        }
        const std::uint64_t step =
            std::min<std::uint64_t>(got - i, plan.runs[run].second - posInRow);
        i += static_cast<std::size_t>(step);
        posInRow += step;
        if (posInRow == plan.runs[run].second) {
          posInRow = 0;
          if (++rowInRun == plan.runs[run].first) {
            rowInRun = 0;
            ++run;
          }
        }
      }
      produced += got;
      if (status == Z_BUF_ERROR && got == 0) break;  // needs the next chunk's input
    }
  }
  ::inflateEnd(&z);
  if (!fault.empty()) throw Error(where + fault);
  if (produced < plan.total)
    throw Error(where + "the image data ends after " + std::to_string(produced) + " of the " +
                std::to_string(plan.total) + " bytes its " + std::to_string(width) + "x" +
                std::to_string(height) + " header declares");
  if (status != Z_STREAM_END) throw Error(where + "the image data stream does not end");
}

}  // namespace clhair
