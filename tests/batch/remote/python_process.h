// Test support: a Python script run by Debian's /usr/bin/python3 (the python3 first on PATH may
// be an interpreter without Debian's modules) as a child process, killed when this goes out of
// scope (or when the test process dies), with its stdout readable under a deadline.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <string>
#include <vector>

namespace tavis::remote::testing {

inline constexpr const char* kDebianPython = "/usr/bin/python3";

class PythonProcess {
 public:
  // Starts `script` (a path) with `args`. Throws std::runtime_error when /usr/bin/python3 is
  // missing or the process cannot be started; stderr goes to the test's stderr.
  PythonProcess(const std::string& script, const std::vector<std::string>& args);
  ~PythonProcess();
  PythonProcess(const PythonProcess&) = delete;
  PythonProcess& operator=(const PythonProcess&) = delete;

  // Whether the script is still running (false once it exited, e.g. on an ImportError).
  bool Running();

  // All of stdout until the script exits; throws naming the script when it takes longer than
  // `timeout` or exits with a non-zero status.
  std::string ReadAllOutput(std::chrono::milliseconds timeout);

 private:
  std::string script_;
  pid_t pid_ = -1;
  int stdout_fd_ = -1;
};

// The path of a script in this test folder.
std::string TestScript(const std::string& name);

// A loopback TCP port nothing listens on right now (bound to port 0, then released).
int FreeLoopbackPort();

}  // namespace tavis::remote::testing
