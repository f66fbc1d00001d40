// stderr_capture.cpp — see stderr_capture.h.
#include "cl/stderr_capture.h"

#include <unistd.h>

#include <atomic>

namespace clhair {

namespace {

std::mutex& captureMutex() {
  static std::mutex m;
  return m;
}

std::atomic<bool> capturing{false};

constexpr long kMaxCaptured = 1 << 20;

}  // namespace

void captureDriverOutput(bool on) { capturing = on; }

StderrCapture::StderrCapture() {
  if (!capturing) return;
  lock_ = std::unique_lock<std::mutex>(captureMutex());
  std::fflush(stderr);
  file_ = std::tmpfile();
  if (!file_) return;
  saved_ = ::dup(2);
  if (saved_ < 0 || ::dup2(::fileno(file_), 2) < 0) {
    if (saved_ >= 0) ::close(saved_);
    saved_ = -1;
    std::fclose(file_);
    file_ = nullptr;
  }
}

StderrCapture::~StderrCapture() { finish(); }

std::string StderrCapture::finish() {
  if (!file_) return {};
  std::fflush(stderr);
  ::dup2(saved_, 2);
  ::close(saved_);
  saved_ = -1;
  std::string text;
  if (std::fseek(file_, 0, SEEK_SET) == 0) {
    char buf[4096];
    std::size_t n;
    while (static_cast<long>(text.size()) < kMaxCaptured &&
           (n = std::fread(buf, 1, sizeof(buf), file_)) > 0)
      text.append(buf, n);
  }
  std::fclose(file_);
  file_ = nullptr;
  return text;
}

}  // namespace clhair
