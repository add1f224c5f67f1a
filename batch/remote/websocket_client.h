// A blocking websocket client for one connection (RFC 6455 subset of policy-interfaces.md §A1):
// opening handshake, masked binary frames out, whole messages in, pings answered while reading,
// the close handshake. Single-threaded: pings are answered only inside Receive/ServicePending.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "batch/remote/tcp_socket.h"
#include "batch/remote/websocket_reader.h"
#include "batch/remote/websocket_url.h"

namespace tavis::batch::remote {

struct WebSocketMessage {
  bool text = false;  // a text frame: for openpi, the server's traceback
  std::vector<std::uint8_t> payload;
};

class WebSocketClient {
 public:
  // Connects and completes the handshake before `deadline`. Throws ConnectFailed, RemoteTimeout,
  // or WebSocketProtocolError for a bad upgrade answer.
  WebSocketClient(const WebSocketUrl& url, Deadline deadline, const std::vector<std::string>& extra_headers = {},
                  std::uint64_t max_message_bytes = std::uint64_t{1} << 32);
  // Sends a normal close (1000) if the connection is still open; never throws.
  ~WebSocketClient();
  WebSocketClient(const WebSocketClient&) = delete;
  WebSocketClient& operator=(const WebSocketClient&) = delete;

  void SendBinary(const std::vector<std::uint8_t>& payload, Deadline deadline);

  // The next text or binary message. Throws ConnectionLost when the server closes (with its
  // code and reason) or the connection drops, RemoteTimeout at the deadline,
  // WebSocketProtocolError for bad frames.
  WebSocketMessage Receive(Deadline deadline);

  // Handles the frames that have already arrived without waiting: pings are answered, messages
  // kept for Receive. Returns false once the connection is closed.
  bool ServicePending();

  bool open() const { return open_; }

 private:
  struct UpgradedConnection {
    TcpSocket socket;
    std::vector<std::uint8_t> first_bytes;  // frames that arrived with the 101 response
  };
  static UpgradedConnection ConnectAndUpgrade(const WebSocketUrl& url, Deadline deadline,
                                              const std::vector<std::string>& extra_headers);
  WebSocketClient(UpgradedConnection connection, std::uint64_t max_message_bytes);

  // Reads socket bytes into the reader until one event is complete and returns true. With
  // `wait` false it returns false as soon as no complete event is buffered and the socket has
  // nothing to read; with `wait` true it throws RemoteTimeout at the deadline instead.
  bool ReadEvent(Deadline deadline, bool wait, WebSocketEvent& event);
  // Answers a ping, records a close (and throws ConnectionLost); returns a data message.
  std::optional<WebSocketMessage> Handle(WebSocketEvent& event);
  void SendFrame(Opcode opcode, const std::uint8_t* payload, std::size_t size, Deadline deadline);

  TcpSocket socket_;
  WebSocketReader reader_;
  std::deque<WebSocketMessage> pending_;  // messages ServicePending read ahead of Receive
  std::vector<std::uint8_t> receive_buffer_;
  std::mt19937 mask_generator_;  // RFC 6455 masks only need to be unpredictable to proxies
  bool open_ = true;
};

}  // namespace tavis::batch::remote
