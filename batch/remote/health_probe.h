// openpi's readiness probe: a plain HTTP "GET /healthz" answered 200 once the server listens
// (it binds only after loading the model, so until then connections are refused).
#pragma once

#include <chrono>
#include <string>

#include "batch/remote/websocket_url.h"

namespace tavis::remote {

// Asks http://host:port/healthz every `retry_interval` until it answers 200, for at most
// `timeout`. Throws RemoteTimeout naming the address, the time waited and the last failure
// (e.g. "Connection refused", "HTTP 503").
void WaitForHealthz(const WebSocketUrl& server, std::chrono::milliseconds timeout,
                    std::chrono::milliseconds retry_interval = std::chrono::milliseconds(100));

}  // namespace tavis::remote
