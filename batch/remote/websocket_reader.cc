#include "batch/remote/websocket_reader.h"

#include <string>

#include "batch/remote/remote_error.h"

namespace tavis::batch::remote {
namespace {

// RFC 6455 section 7.1.5: the code reported for a close frame without a status.
constexpr std::uint16_t kNoStatusReceived = 1005;

WebSocketEvent ControlEvent(const Frame& frame, std::uint64_t offset) {
  WebSocketEvent event;
  if (frame.opcode == Opcode::kPing) event.kind = WebSocketEvent::Kind::kPing;
  if (frame.opcode == Opcode::kPong) event.kind = WebSocketEvent::Kind::kPong;
  if (frame.opcode != Opcode::kClose) {
    event.payload = frame.payload;
    return event;
  }
  event.kind = WebSocketEvent::Kind::kClose;
  if (frame.payload.size() == 1) {
    throw WebSocketProtocolError("websocket close frame at stream byte " + std::to_string(offset) +
                                 " has a 1-byte payload (a status code needs 2)");
  }
  if (frame.payload.empty()) {
    event.close_code = kNoStatusReceived;
    return event;
  }
  event.close_code = static_cast<std::uint16_t>(frame.payload[0] << 8 | frame.payload[1]);
  event.payload.assign(frame.payload.begin() + 2, frame.payload.end());
  return event;
}

}  // namespace

void WebSocketReader::Append(const std::uint8_t* data, std::size_t size) {
  if (read_position_ > 0 && read_position_ * 2 >= buffer_.size()) {
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(read_position_));
    read_position_ = 0;
  }
  buffer_.insert(buffer_.end(), data, data + size);
}

std::optional<WebSocketEvent> WebSocketReader::Next() {
  while (true) {
    const std::uint64_t open_size = open_message_ ? open_message_->payload.size() : 0;
    Frame frame;
    const std::uint64_t offset = stream_position_;
    const std::size_t consumed = ParseServerFrame(buffer_.data() + read_position_, buffer_.size() - read_position_,
                                                  max_message_bytes_ - open_size, offset, frame);
    if (consumed == 0) return std::nullopt;
    read_position_ += consumed;
    stream_position_ += consumed;

    if (frame.opcode >= Opcode::kClose) return ControlEvent(frame, offset);
    if (frame.opcode == Opcode::kContinuation) {
      if (!open_message_) {
        throw WebSocketProtocolError("websocket continuation frame at stream byte " + std::to_string(offset) +
                                     " with no fragmented message open");
      }
      open_message_->payload.insert(open_message_->payload.end(), frame.payload.begin(), frame.payload.end());
    } else {
      if (open_message_) {
        throw WebSocketProtocolError("websocket data frame at stream byte " + std::to_string(offset) +
                                     " while a fragmented message is still open");
      }
      open_message_ =
          WebSocketEvent{frame.opcode == Opcode::kText ? WebSocketEvent::Kind::kText : WebSocketEvent::Kind::kBinary,
                         std::move(frame.payload), 0};
    }
    if (frame.fin) {
      std::optional<WebSocketEvent> message = std::move(open_message_);
      open_message_.reset();
      return message;
    }
  }
}

}  // namespace tavis::batch::remote
