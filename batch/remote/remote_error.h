// The failures of the policy-server client, as distinct types so a caller can tell a fault it
// may recover from (a dropped connection: reconnect) from one it must report (a server error,
// a timeout, malformed bytes).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

namespace tavis::batch::remote {

// Bytes that break the msgpack or msgpack-numpy rules; `offset` is where in the message.
class MsgpackError : public std::runtime_error {
 public:
  MsgpackError(const std::string& what, std::size_t offset)
      : std::runtime_error("msgpack: " + what + " at byte offset " + std::to_string(offset)), offset_(offset) {}
  std::size_t offset() const { return offset_; }

 private:
  std::size_t offset_;
};

// Bytes from the server that break RFC 6455 (or the HTTP upgrade); the connection is unusable.
class WebSocketProtocolError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A message longer than the client accepts (OpenpiSessionOptions::max_reply_bytes), refused from
// its frame header before its bytes are read; the connection is unusable afterwards.
class MessageTooLarge : public WebSocketProtocolError {
 public:
  using WebSocketProtocolError::WebSocketProtocolError;
};

// A reply that arrived whole but is not a usable openpi reply: bytes that are not msgpack or
// msgpack-numpy (an ndarray whose data does not fill its shape, an absurd shape, an unknown
// dtype), not a map, or over the size limit. It ends only the episode that asked (the policy
// turns it into that env's fault); the session stays usable (after a reconnect if needed).
class MalformedReply : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// A deadline passed: connecting, waiting for a reply, or waiting for /healthz.
class RemoteTimeout : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// No TCP connection could be made (refused, unresolvable host).
class ConnectFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The connection ended (close frame, EOF or reset) without a server error: reconnecting may help.
// `close_code` is the close frame's status, 1006 when there was none (RFC 6455 section 7.1.5).
class ConnectionLost : public std::runtime_error {
 public:
  ConnectionLost(const std::string& what, std::uint16_t close_code, std::string close_reason = "")
      : std::runtime_error(what), close_code_(close_code), close_reason_(std::move(close_reason)) {}
  std::uint16_t close_code() const { return close_code_; }
  const std::string& close_reason() const { return close_reason_; }

 private:
  std::uint16_t close_code_;
  std::string close_reason_;
};

// The policy server failed: openpi sends the Python traceback as a text frame, then closes with
// 1011. Not retried, since the same observation would fail again.
class PolicyServerError : public std::runtime_error {
 public:
  PolicyServerError(const std::string& traceback, std::uint16_t close_code, const std::string& close_reason)
      : std::runtime_error("policy server error (close " + std::to_string(close_code) +
                           (close_reason.empty() ? "" : ": " + close_reason) + "):\n" + traceback),
        traceback_(traceback),
        close_code_(close_code) {}
  const std::string& traceback() const { return traceback_; }
  std::uint16_t close_code() const { return close_code_; }

 private:
  std::string traceback_;
  std::uint16_t close_code_;
};

}  // namespace tavis::batch::remote
