// Test support: policy_server.py on a free loopback port, ready (its /healthz answers) once
// constructed unless asked not to wait; killed when this goes out of scope.
#pragma once

#include <string>
#include <vector>

#include "batch/remote/websocket_url.h"
#include "tests/batch/remote/test_scripts.h"

namespace tavis::batch::remote::testing {

class PolicyServerProcess {
 public:
  // Runs policy_server.py --port PORT `args`.
  explicit PolicyServerProcess(const std::vector<std::string>& args, bool wait_ready = true);

  // Waits (at most 20 s) until /healthz answers; throws at once, naming the likely cause, if the
  // script exits instead.
  void WaitUntilReady();
  WebSocketUrl url() const { return {"127.0.0.1", port_, "/"}; }
  std::string address() const { return "ws://127.0.0.1:" + std::to_string(port_); }

 private:
  int port_;
  tavis::testing::ChildProcess process_;
};

}  // namespace tavis::batch::remote::testing
