// error.h — the one exception type clhair throws.
//
// Every failure a user can cause or meet (bad input, missing device capability, an OpenCL
// call that fails) becomes a clhair::Error whose message is one readable line: what
// failed, where, the values that matter and, when it helps, a hint. Build failures carry
// the device, options and full build log after that first line.
#pragma once

#include <stdexcept>
#include <string>

namespace clhair {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace clhair
