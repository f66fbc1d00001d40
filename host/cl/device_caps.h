// device_caps.h — reading a device's capability strings (device.cpp, device_programs.cpp).
#pragma once

#include <string>

namespace clhair {

// Whether the space-separated extension list names `ext`.
bool hasExtension(const std::string& extensions, const std::string& ext);
// "OpenCL C 1.2 ..." -> 120 (120 when the string says nothing readable).
int clcVersionNumber(const std::string& clc);

}  // namespace clhair
