// error.h — the one exception type clhair throws.
//
// Every failure a user can cause or meet (bad input, missing device capability, an OpenCL
// call that fails) becomes a clhair::Error whose message is one readable line: what
// failed, where, the values that matter and, when it helps, a hint. What does not fit on a
// line (a build log, the list of devices) goes into details(), which the command prints only
// when asked (--verbose) or writes to a log file that its error line names.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

namespace clhair {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
  Error(const std::string& message, std::string details)
      : std::runtime_error(message),
        details_(std::make_shared<const std::string>(std::move(details))) {}

  // Lines that explain the message further; "" when there are none.
  const std::string& details() const {
    static const std::string none;
    return details_ ? *details_ : none;
  }

 private:
  std::shared_ptr<const std::string> details_;  // shared: copying an exception cannot throw
};

}  // namespace clhair
