// The status line and headers of an HTTP/1.1 response: what the websocket upgrade and the
// /healthz probe read before anything else.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "batch/remote/tcp_socket.h"

namespace tavis::batch::remote {

struct HttpResponseHead {
  int status = 0;
  std::string reason;
  std::vector<std::pair<std::string, std::string>> headers;  // names lower-cased, values trimmed

  // The value of the first header named `name` (any case), if present.
  std::optional<std::string> Header(std::string_view name) const;
};

// Parses "HTTP/1.x CODE REASON\r\n" and "Name: value\r\n" lines (the head up to, not including,
// the blank line). Throws WebSocketProtocolError quoting the offending line.
HttpResponseHead ParseHttpResponseHead(std::string_view head);

struct HttpResponseStart {
  HttpResponseHead head;
  std::vector<std::uint8_t> rest;  // bytes after the blank line: the body, or the first frames
};

// Reads from `socket` up to the blank line ending the head (at most 16 KiB), then parses it.
// Throws RemoteTimeout at the deadline, ConnectionLost when the peer closes first.
HttpResponseStart ReadHttpResponseStart(TcpSocket& socket, Deadline deadline);

}  // namespace tavis::batch::remote
