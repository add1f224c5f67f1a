#include "batch/remote/tcp_socket.h"

#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <memory>
#include <utility>

#include "batch/remote/remote_error.h"

namespace tavis::batch::remote {
namespace {

int MillisecondsUntil(Deadline deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  if (left <= 0) return 0;
  return left > 60'000 ? 60'000 : static_cast<int>(left) + 1;  // +1: poll rounds down
}

// Connects `descriptor` (non-blocking) to one address; returns 0 or the errno of the failure.
int ConnectOne(int descriptor, const addrinfo& address, Deadline deadline) {
  if (connect(descriptor, address.ai_addr, address.ai_addrlen) == 0) return 0;
  if (errno != EINPROGRESS) return errno;
  while (true) {
    pollfd entry{descriptor, POLLOUT, 0};
    const int ready = poll(&entry, 1, MillisecondsUntil(deadline));
    if (ready < 0 && errno == EINTR) continue;
    if (ready < 0) return errno;
    if (ready == 0) {
      if (Clock::now() >= deadline) return ETIMEDOUT;
      continue;
    }
    int error = 0;
    socklen_t length = sizeof error;
    getsockopt(descriptor, SOL_SOCKET, SO_ERROR, &error, &length);
    return error;
  }
}

}  // namespace

TcpSocket TcpSocket::Connect(const std::string& host, int port, Deadline deadline) {
  const std::string peer = host + ":" + std::to_string(port);
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (const int status = getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found); status != 0) {
    throw ConnectFailed("cannot resolve policy server host '" + host + "': " + gai_strerror(status));
  }
  const std::unique_ptr<addrinfo, decltype(&freeaddrinfo)> addresses(found, &freeaddrinfo);
  int last_error = 0;
  for (const addrinfo* address = found; address != nullptr; address = address->ai_next) {
    const int descriptor =
        socket(address->ai_family, address->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, address->ai_protocol);
    if (descriptor < 0) {
      last_error = errno;
      continue;
    }
    last_error = ConnectOne(descriptor, *address, deadline);
    if (last_error == 0) {
      const int on = 1;  // requests are single writes awaited by the peer: do not delay them
      setsockopt(descriptor, IPPROTO_TCP, TCP_NODELAY, &on, sizeof on);
      return TcpSocket(descriptor, peer);
    }
    close(descriptor);
    if (last_error == ETIMEDOUT) break;
  }
  if (last_error == ETIMEDOUT) throw RemoteTimeout("timed out connecting to policy server " + peer);
  throw ConnectFailed("cannot connect to policy server " + peer + ": " + std::strerror(last_error));
}

TcpSocket::TcpSocket(TcpSocket&& other) noexcept
    : descriptor_(std::exchange(other.descriptor_, -1)), peer_(std::move(other.peer_)) {}

TcpSocket& TcpSocket::operator=(TcpSocket&& other) noexcept {
  if (this != &other) {
    if (descriptor_ >= 0) close(descriptor_);
    descriptor_ = std::exchange(other.descriptor_, -1);
    peer_ = std::move(other.peer_);
  }
  return *this;
}

TcpSocket::~TcpSocket() {
  if (descriptor_ >= 0) close(descriptor_);
}

bool TcpSocket::WaitFor(short events, Deadline deadline) const {
  while (true) {
    pollfd entry{descriptor_, events, 0};
    const int ready = poll(&entry, 1, MillisecondsUntil(deadline));
    if (ready > 0) return true;
    if (ready < 0 && errno != EINTR) throw ConnectionLost("poll on " + peer_ + ": " + std::strerror(errno), 1006);
    if (ready == 0 && Clock::now() >= deadline) return false;
  }
}

bool TcpSocket::Readable() const {
  pollfd entry{descriptor_, POLLIN, 0};
  return poll(&entry, 1, 0) > 0;
}

void TcpSocket::SendAll(const std::uint8_t* data, std::size_t size, Deadline deadline) {
  std::size_t sent = 0;
  while (sent < size) {
    const ssize_t count = send(descriptor_, data + sent, size - sent, MSG_NOSIGNAL);
    if (count >= 0) {
      sent += static_cast<std::size_t>(count);
      continue;
    }
    if (errno == EINTR) continue;
    if (errno != EAGAIN && errno != EWOULDBLOCK) {
      throw ConnectionLost("sending to policy server " + peer_ + ": " + std::strerror(errno), 1006);
    }
    if (!WaitFor(POLLOUT, deadline)) {
      throw RemoteTimeout("timed out sending to policy server " + peer_ + " (" + std::to_string(sent) + " of " +
                          std::to_string(size) + " bytes sent)");
    }
  }
}

std::size_t TcpSocket::ReceiveSome(std::uint8_t* buffer, std::size_t capacity, Deadline deadline) {
  while (true) {
    const ssize_t count = recv(descriptor_, buffer, capacity, 0);
    if (count >= 0) return static_cast<std::size_t>(count);
    if (errno == EINTR) continue;
    if (errno != EAGAIN && errno != EWOULDBLOCK) {
      throw ConnectionLost("receiving from policy server " + peer_ + ": " + std::strerror(errno), 1006);
    }
    if (!WaitFor(POLLIN, deadline)) throw RemoteTimeout("timed out waiting for policy server " + peer_);
  }
}

}  // namespace tavis::batch::remote
