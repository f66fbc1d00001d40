// device_caps.cpp — see device_caps.h.
#include "cl/device_caps.h"

#include <cstdio>
#include <sstream>

namespace clhair {

bool hasExtension(const std::string& extensions, const std::string& ext) {
  std::istringstream ss(extensions);
  std::string token;
  while (ss >> token)
    if (token == ext) return true;
  return false;
}

// "OpenCL C 1.2 ..." -> 120
int clcVersionNumber(const std::string& clc) {
  auto pos = clc.find("OpenCL C ");
  if (pos == std::string::npos) return 120;
  int major = 1, minor = 2;
  if (std::sscanf(clc.c_str() + pos + 9, "%d.%d", &major, &minor) != 2) return 120;
  return major * 100 + minor * 10;
}

}  // namespace clhair
