// One connection to an openpi policy server, as openpi's websocket_client_policy drives it:
// connect, keep the metadata message the server sends first, then lock-step requests, each an
// observation map answered by one reply map (policy-interfaces.md §A1).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "batch/remote/msgpack_value.h"
#include "batch/remote/websocket_client.h"
#include "batch/remote/websocket_url.h"

namespace tavis::batch::remote {

// The largest reply accepted by default: a chunk of 100,000 rows of 19 float64 (15.2 MB) with
// room for the server's timing fields. openpi's chunks are tens of rows.
inline constexpr std::uint64_t kDefaultMaxReplyBytes = std::uint64_t{16} << 20;

struct OpenpiSessionOptions {
  std::string url;                                    // ws://HOST:PORT
  std::optional<std::string> api_key;                 // sent as "Authorization: Api-Key <key>", as openpi's client does
  std::chrono::milliseconds connect_timeout{10'000};  // TCP connect, handshake and metadata
  // Send plus reply; generous because a server's first inference may compile its model.
  std::chrono::milliseconds reply_timeout{300'000};
  // A reply (or metadata message) over this many bytes is refused from its frame header, before
  // its bytes are read, so a runaway server cannot exhaust memory (the cell setting max_reply_mb).
  std::uint64_t max_reply_bytes = kDefaultMaxReplyBytes;
};

struct InferResult {
  Value reply;                 // the decoded reply map ("actions", "server_timing", ...)
  double round_trip_ms = 0.0;  // from the request's first byte sent to the reply's last byte read
  bool reconnected = false;    // this request needed a new connection (the previous one had closed)
};

class OpenpiSession {
 public:
  // Connects and reads the metadata. Throws ConnectFailed, RemoteTimeout,
  // WebSocketProtocolError, MsgpackError, or PolicyServerError.
  explicit OpenpiSession(OpenpiSessionOptions options);

  // The server's first message, decoded (often an empty map; openpi defines no schema).
  const Value& metadata() const { return metadata_; }

  // Sends `observation` (a map) and waits for the reply map. A connection that closed without a
  // server error (e.g. the server's keepalive timeout while we were busy) is re-opened once and
  // the request sent again. Throws PolicyServerError with the server's traceback (text frame,
  // then close 1011), RemoteTimeout (after which the next request uses a new connection, so a
  // late reply is never taken for its answer), ConnectFailed when re-opening fails, MsgpackError or
  // WebSocketProtocolError for bad frames, MalformedReply (a std::invalid_argument) for a reply
  // that is not msgpack(-numpy), not a map, or over max_reply_bytes: the caller may end only the
  // episode that asked, and the next request works (on a new connection after an oversize reply).
  InferResult Infer(const Value& observation);

  // Answers pings that arrived since the last call, without waiting; call it during long pauses
  // between requests (a reset) so the server's keepalive does not drop the connection.
  void ServiceKeepalive();

  // Connections opened after the first one.
  int reconnects() const { return connections_ - 1; }

 private:
  void Connect();
  // Reads the next message; a text message is the server's traceback and is thrown.
  std::vector<std::uint8_t> ReceiveBinary(Deadline deadline);

  OpenpiSessionOptions options_;
  WebSocketUrl url_;
  std::unique_ptr<WebSocketClient> client_;
  Value metadata_;
  int connections_ = 0;
};

}  // namespace tavis::batch::remote
