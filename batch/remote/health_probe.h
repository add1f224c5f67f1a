// openpi's readiness probe: a plain HTTP "GET /healthz" answered 200 once the server listens
// (it binds only after loading the model, so until then connections are refused). Servers that
// speak openpi's websocket protocol without its /healthz (LeRobot's and others' ports) are
// accepted too: once one answers a plain HTTP request at all with "no such route" (404, 400,
// 405, 426 Upgrade Required) or closes it unanswered, the client connects instead.
#pragma once

#include <chrono>
#include <string>

#include "batch/remote/websocket_url.h"

namespace tavis::batch::remote {

enum class Readiness {
  kHealthy,    // /healthz answered 200
  kNoHealthz,  // the server listens but has no /healthz: connect to find out
};

// Asks http://host:port/healthz every `retry_interval` until it answers 200 or shows that the
// server has no /healthz, for at most `timeout`; a refused connection or a 5xx (a server still
// loading) is asked again. Throws RemoteTimeout naming the address, the time waited and the last
// failure (e.g. "Connection refused", "HTTP 503").
Readiness WaitForHealthz(const WebSocketUrl& server, std::chrono::milliseconds timeout,
                         std::chrono::milliseconds retry_interval = std::chrono::milliseconds(100));

}  // namespace tavis::batch::remote
