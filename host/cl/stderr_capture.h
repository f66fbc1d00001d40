// stderr_capture.h — what the process writes to stderr while a driver builds a program.
//
// An OpenCL compiler may print its own lines straight to file descriptor 2 besides the build
// log (PoCL's clang: "2 errors generated."), so a failed build would print more than clhair's
// one error line. A StderrCapture points descriptor 2 at a temporary file for its lifetime and
// hands back what was written there; builds keep it as part of their details. Descriptor 2 is
// process-wide, so captures are serialised by a lock, and a thread printing meanwhile lands in
// the capture too (clhair prints nothing from other threads while it builds). When no
// temporary file can be made (a full /tmp), nothing is captured and stderr stays as it was.
// Capturing is off until a program turns it on (the clhair command does): a library user, or a
// sanitizer report from inside a driver, keeps stderr as it is.
#pragma once

#include <cstdio>
#include <mutex>
#include <string>

namespace clhair {

// Turns capturing on or off for the whole process (off by default).
void captureDriverOutput(bool on);

class StderrCapture {
 public:
  StderrCapture();
  ~StderrCapture();
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;

  // Restores stderr and returns what was written to it (at most 1 MiB); "" after the first call.
  std::string finish();

 private:
  std::unique_lock<std::mutex> lock_;
  std::FILE* file_ = nullptr;
  int saved_ = -1;
};

}  // namespace clhair
