#include "batch/remote/health_probe.h"

#include <algorithm>
#include <optional>
#include <thread>

#include "batch/remote/http_response.h"
#include "batch/remote/remote_error.h"
#include "batch/remote/tcp_socket.h"

namespace tavis::batch::remote {
namespace {

struct Probe {
  std::optional<Readiness> ready;  // empty: ask again
  std::string failure;             // what went wrong, when not ready
};

// HTTP statuses with which a websocket server without a /healthz route answers a plain GET.
bool MeansNoHealthz(int status) { return status == 400 || status == 404 || status == 405 || status == 426; }

Probe ProbeOnce(const WebSocketUrl& server, Deadline deadline) {
  std::optional<TcpSocket> socket;
  try {
    socket.emplace(TcpSocket::Connect(server.host, server.port, deadline));
  } catch (const std::runtime_error& error) {
    return {std::nullopt, error.what()};  // not listening (yet)
  }
  try {
    const std::string request =
        "GET /healthz HTTP/1.1\r\nHost: " + server.Authority() + "\r\nConnection: close\r\n\r\n";
    socket->SendAll(reinterpret_cast<const std::uint8_t*>(request.data()), request.size(), deadline);
    const HttpResponseStart response = ReadHttpResponseStart(*socket, deadline);
    if (response.head.status == 200) return {Readiness::kHealthy, ""};
    const std::string failure = "HTTP " + std::to_string(response.head.status) + " " + response.head.reason;
    return {MeansNoHealthz(response.head.status) ? std::optional(Readiness::kNoHealthz) : std::nullopt, failure};
  } catch (const RemoteTimeout& error) {
    return {std::nullopt, error.what()};
  } catch (const std::runtime_error&) {
    // It accepted the connection but did not speak HTTP back (closed it, or answered garbage):
    // a listening server without /healthz; the websocket handshake will tell.
    return {Readiness::kNoHealthz, ""};
  }
}

}  // namespace

Readiness WaitForHealthz(const WebSocketUrl& server, std::chrono::milliseconds timeout,
                         std::chrono::milliseconds retry_interval) {
  const Clock::time_point start = Clock::now();
  const Deadline deadline = start + timeout;
  std::string failure;
  do {
    const Probe probe = ProbeOnce(server, deadline);
    if (probe.ready) return *probe.ready;
    failure = probe.failure;
    std::this_thread::sleep_for(std::min<Clock::duration>(
        retry_interval, std::max<Clock::duration>(deadline - Clock::now(), Clock::duration::zero())));
  } while (Clock::now() < deadline);
  const auto waited = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - start).count();
  throw RemoteTimeout("policy server " + server.Authority() + " not ready: /healthz did not answer 200 within " +
                      std::to_string(waited) + " ms (last attempt: " + failure + ")");
}

}  // namespace tavis::batch::remote
