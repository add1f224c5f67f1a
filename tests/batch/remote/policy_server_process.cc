#include "tests/batch/remote/policy_server_process.h"

#include <chrono>
#include <stdexcept>

#include "batch/remote/health_probe.h"
#include "batch/remote/remote_error.h"
#include "batch/remote/tcp_socket.h"

namespace tavis::batch::remote::testing {
namespace {

std::vector<std::string> WithPort(int port, std::vector<std::string> args) {
  args.insert(args.begin(), {"--port", std::to_string(port)});
  return args;
}

}  // namespace

PolicyServerProcess::PolicyServerProcess(const std::vector<std::string>& args, bool wait_ready)
    : port_(tavis::testing::FreeLoopbackPort()),
      process_(tavis::testing::kDebianPython,
               tavis::testing::ScriptArgs(TestScript("policy_server.py"), WithPort(port_, args)), kPythonHint) {
  if (wait_ready) WaitUntilReady();
}

void PolicyServerProcess::WaitUntilReady() {
  const Deadline deadline = Clock::now() + std::chrono::milliseconds(20'000);
  while (true) {
    try {
      WaitForHealthz(url(), std::chrono::milliseconds(250));
      return;
    } catch (const RemoteTimeout&) {
      if (!process_.Running()) {
        throw std::runtime_error(
            "policy_server.py exited before serving (its stderr above says why; are "
            "python3-websockets, python3-msgpack and python3-numpy installed?)");
      }
      if (Clock::now() > deadline) throw;
    }
  }
}

}  // namespace tavis::batch::remote::testing
