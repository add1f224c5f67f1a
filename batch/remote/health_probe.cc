#include "batch/remote/health_probe.h"

#include <algorithm>
#include <thread>

#include "batch/remote/http_response.h"
#include "batch/remote/remote_error.h"
#include "batch/remote/tcp_socket.h"

namespace tavis::remote {
namespace {

// One probe; returns an empty string when the server answered 200, else what went wrong.
std::string ProbeOnce(const WebSocketUrl& server, Deadline deadline) {
  try {
    TcpSocket socket = TcpSocket::Connect(server.host, server.port, deadline);
    const std::string request = "GET /healthz HTTP/1.1\r\nHost: " + server.Authority() + "\r\nConnection: close\r\n\r\n";
    socket.SendAll(reinterpret_cast<const std::uint8_t*>(request.data()), request.size(), deadline);
    const HttpResponseStart response = ReadHttpResponseStart(socket, deadline);
    if (response.head.status == 200) return "";
    return "HTTP " + std::to_string(response.head.status) + " " + response.head.reason;
  } catch (const std::runtime_error& error) {
    return error.what();
  }
}

}  // namespace

void WaitForHealthz(const WebSocketUrl& server, std::chrono::milliseconds timeout,
                    std::chrono::milliseconds retry_interval) {
  const Clock::time_point start = Clock::now();
  const Deadline deadline = start + timeout;
  std::string failure;
  do {
    failure = ProbeOnce(server, deadline);
    if (failure.empty()) return;
    std::this_thread::sleep_for(std::min<Clock::duration>(retry_interval, std::max<Clock::duration>(deadline - Clock::now(), Clock::duration::zero())));
  } while (Clock::now() < deadline);
  const auto waited = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - start).count();
  throw RemoteTimeout("policy server " + server.Authority() + " not ready: /healthz did not answer 200 within " +
                      std::to_string(waited) + " ms (last attempt: " + failure + ")");
}

}  // namespace tavis::remote
