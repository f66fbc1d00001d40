// cl_error.h — OpenCL status codes to names, and the conversion of the C++ bindings'
// exceptions into clhair::Error with the failing call, the code's name and the stage.
#pragma once

#include <string>

#include "cl/opencl.h"
#include "clhair/error.h"

namespace clhair {

const char* clErrorName(cl_int code);

// Rethrows the active exception as clhair::Error prefixed with `stage`. Use inside catch.
[[noreturn]] void rethrowAsClhairError(const std::string& stage);

// Runs f(); an OpenCL failure inside becomes clhair::Error naming `stage`.
template <typename F>
auto clCall(const std::string& stage, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (...) {
    rethrowAsClhairError(stage);
  }
}

}  // namespace clhair
