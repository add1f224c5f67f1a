// Exit statuses beyond main's "0 done, 1 an error", for a command whose status means more (`tavis
// compare`: 1 a regression, 2 bad input, so that a CI gate can tell them apart).
#pragma once

#include <stdexcept>
#include <string>

namespace tavis::tools {

// Thrown by a command's callback: main prints the message, when there is one, as an error
// ("tavis: error: ..."), and exits with `status`.
class ExitStatus : public std::runtime_error {
 public:
  ExitStatus(int status, const std::string& message) : std::runtime_error(message), status_(status) {}
  int status() const { return status_; }

 private:
  int status_;
};

// The status a usage error (an unknown flag, a bad value, a missing argument) exits with: 1, unless
// the command being parsed set another with SetUsageErrorStatus (from its preparse callback, which
// runs before its arguments are read).
void SetUsageErrorStatus(int status);
int UsageErrorStatus();

}  // namespace tavis::tools
