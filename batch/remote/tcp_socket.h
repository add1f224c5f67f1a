// A connected TCP socket (POSIX) whose every wait ends at a deadline, so no call of the client
// can hang on a silent server.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>

namespace tavis::batch::remote {

using Clock = std::chrono::steady_clock;
using Deadline = Clock::time_point;

class TcpSocket {
 public:
  // Resolves `host` and connects, trying each address until one accepts. Throws ConnectFailed
  // naming host:port and the system error (e.g. "Connection refused"), RemoteTimeout when the
  // deadline passes first.
  static TcpSocket Connect(const std::string& host, int port, Deadline deadline);

  TcpSocket(TcpSocket&& other) noexcept;
  TcpSocket& operator=(TcpSocket&& other) noexcept;
  TcpSocket(const TcpSocket&) = delete;
  TcpSocket& operator=(const TcpSocket&) = delete;
  ~TcpSocket();

  // Sends all bytes. Throws ConnectionLost when the peer has gone (no SIGPIPE is raised),
  // RemoteTimeout when the deadline passes first.
  void SendAll(const std::uint8_t* data, std::size_t size, Deadline deadline);

  // Reads what has arrived, waiting until some has or the deadline passes: returns the count,
  // 0 at the peer's orderly shutdown. Throws RemoteTimeout at the deadline, ConnectionLost on a
  // reset. A deadline in the past only takes what is already there (RemoteTimeout if nothing).
  std::size_t ReceiveSome(std::uint8_t* buffer, std::size_t capacity, Deadline deadline);

  // Whether bytes (or the peer's shutdown) are waiting to be read, without blocking.
  bool Readable() const;

  const std::string& peer() const { return peer_; }

 private:
  TcpSocket(int descriptor, std::string peer) : descriptor_(descriptor), peer_(std::move(peer)) {}
  // Waits for `events` (POLLIN or POLLOUT) until the deadline; false when it passed.
  bool WaitFor(short events, Deadline deadline) const;

  int descriptor_ = -1;
  std::string peer_;  // "host:port", for error messages
};

}  // namespace tavis::batch::remote
