// Test support: a program (an independent reader or a counterpart server: Debian's Python, Node)
// run as a child process, killed when this goes out of scope or when the test process dies, with
// its stdout readable under a deadline.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <string>
#include <vector>

namespace tavis::testing {

// Debian's interpreter: the python3 first on PATH may be one without Debian's modules.
inline constexpr const char* kDebianPython = "/usr/bin/python3";
inline constexpr const char* kNode = "/usr/bin/node";

class ChildProcess {
 public:
  // Starts `program` (an absolute path) with `args`; `hint` is appended to failure messages
  // (e.g. which packages the program needs). Throws std::runtime_error when the program is
  // missing or cannot be started; stderr goes to the test's stderr.
  ChildProcess(const std::string& program, const std::vector<std::string>& args, std::string hint = "");
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // Whether the program is still running (false once it exited).
  bool Running();

  // All of stdout until the program exits; throws naming the program and its first argument
  // when it takes longer than `timeout` or exits with a non-zero status.
  std::string ReadAllOutput(std::chrono::milliseconds timeout);

 private:
  std::string description_;  // program and first argument, for messages
  std::string hint_;
  pid_t pid_ = -1;
  int stdout_fd_ = -1;
};

// Runs `script` with Debian's /usr/bin/python3 (the counterpart servers and PyAV checks).
inline std::vector<std::string> ScriptArgs(const std::string& script, const std::vector<std::string>& args) {
  std::vector<std::string> all{script};
  all.insert(all.end(), args.begin(), args.end());
  return all;
}

// A loopback TCP port nothing listens on right now (bound to port 0, then released).
int FreeLoopbackPort();

}  // namespace tavis::testing
