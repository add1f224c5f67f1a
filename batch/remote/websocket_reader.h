// Turns the bytes a server sends into websocket events: whole messages (continuation frames
// joined), pings, pongs and the close. Socket-free, so the same code runs in the client and
// under the fuzz test.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "batch/remote/websocket_frame.h"

namespace tavis::batch::remote {

struct WebSocketEvent {
  enum class Kind { kText, kBinary, kPing, kPong, kClose };
  Kind kind = Kind::kBinary;
  std::vector<std::uint8_t> payload;  // message or ping/pong bytes; the close reason for kClose
  std::uint16_t close_code = 0;       // kClose only: 1005 when the close frame carried no code
};

class WebSocketReader {
 public:
  // `max_message_bytes` bounds one message (all its fragments together).
  explicit WebSocketReader(std::uint64_t max_message_bytes) : max_message_bytes_(max_message_bytes) {}

  void Append(const std::uint8_t* data, std::size_t size);

  // The next complete event, or nullopt until more bytes arrive. Throws WebSocketProtocolError
  // for a bad frame (see ParseServerFrame), a continuation with no message open, a new data
  // frame while one is open, or a close payload of one byte; the reader is unusable afterwards.
  std::optional<WebSocketEvent> Next();

 private:
  std::uint64_t max_message_bytes_;
  std::vector<std::uint8_t> buffer_;
  std::size_t read_position_ = 0;               // bytes of buffer_ already consumed
  std::uint64_t stream_position_ = 0;           // bytes of the stream consumed, for error messages
  std::optional<WebSocketEvent> open_message_;  // a fragmented message waiting for its FIN frame
};

}  // namespace tavis::batch::remote
