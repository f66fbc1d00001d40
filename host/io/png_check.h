// png_check.h — a PNG file's structure and image data checked before a decoder sees it.
//
// libpng prints its own "libpng error: ..." line on stderr for a damaged file before the
// decoder reports it, and a header may declare far more rows than the file holds. So a PNG
// is walked first: the signature, every chunk's length and CRC, IHDR's fields, the order of
// the critical chunks (IHDR first, PLTE before IDAT, consecutive IDATs, IEND last, no unknown
// critical chunk) and the IDAT stream inflated in a small buffer, row by row: every filter
// byte valid and exactly the bytes the header's size needs (Adam7 passes included). Memory
// stays constant and time follows the data the file holds; any fault is one clhair::Error
// line naming the file.
#pragma once

#include <cstdint>
#include <string>

namespace clhair {

// True when `bytes` starts with the PNG signature.
bool looksLikePng(const std::string& bytes);

// Checks a PNG held in memory as above; refuses images of more than `maxPixels` pixels before
// inflating anything.
void checkPng(const std::string& bytes, const std::string& path, std::uint64_t maxPixels);

}  // namespace clhair
