#include "batch/remote/websocket_client.h"

#include <array>
#include <string>

#include "batch/remote/http_response.h"
#include "batch/remote/remote_error.h"
#include "batch/remote/websocket_handshake.h"

namespace tavis::batch::remote {
namespace {

constexpr std::size_t kReceiveChunkBytes = 256 * 1024;
constexpr std::uint16_t kNormalClosure = 1000;
constexpr std::uint16_t kNoStatusReceived = 1005;
constexpr std::uint16_t kAbnormalClosure = 1006;
// How long a control reply (pong, close) may take to send before the connection is given up.
constexpr auto kControlSendTime = std::chrono::seconds(5);

std::string CloseDescription(std::uint16_t code, const std::vector<std::uint8_t>& reason) {
  std::string text = "code " + std::to_string(code);
  if (!reason.empty()) text += ", reason '" + std::string(reason.begin(), reason.end()) + "'";
  return text;
}

}  // namespace

WebSocketClient::UpgradedConnection WebSocketClient::ConnectAndUpgrade(const WebSocketUrl& url, Deadline deadline,
                                                                       const std::vector<std::string>& extra_headers) {
  TcpSocket socket = TcpSocket::Connect(url.host, url.port, deadline);
  const std::string key = MakeWebSocketKey();
  const std::string request = BuildUpgradeRequest(url, key, extra_headers);
  socket.SendAll(reinterpret_cast<const std::uint8_t*>(request.data()), request.size(), deadline);
  HttpResponseStart response = ReadHttpResponseStart(socket, deadline);
  CheckUpgradeResponse(response.head, key);
  return {std::move(socket), std::move(response.rest)};
}

WebSocketClient::WebSocketClient(const WebSocketUrl& url, Deadline deadline,
                                 const std::vector<std::string>& extra_headers, std::uint64_t max_message_bytes)
    : WebSocketClient(ConnectAndUpgrade(url, deadline, extra_headers), max_message_bytes) {}

WebSocketClient::WebSocketClient(UpgradedConnection connection, std::uint64_t max_message_bytes)
    : socket_(std::move(connection.socket)),
      reader_(max_message_bytes),
      receive_buffer_(kReceiveChunkBytes),
      mask_generator_(std::random_device{}()) {
  reader_.Append(connection.first_bytes.data(), connection.first_bytes.size());
}

WebSocketClient::~WebSocketClient() {
  if (!open_) return;
  try {
    const std::array<std::uint8_t, 2> status{kNormalClosure >> 8, kNormalClosure & 0xff};
    SendFrame(Opcode::kClose, status.data(), status.size(), Clock::now() + std::chrono::milliseconds(200));
  } catch (const std::exception&) {
    // The server is gone already; closing the socket is all that is left to do.
  }
}

void WebSocketClient::SendFrame(Opcode opcode, const std::uint8_t* payload, std::size_t size, Deadline deadline) {
  const std::uint32_t mask_bits = mask_generator_();
  const std::array<std::uint8_t, 4> mask{
      static_cast<std::uint8_t>(mask_bits), static_cast<std::uint8_t>(mask_bits >> 8),
      static_cast<std::uint8_t>(mask_bits >> 16), static_cast<std::uint8_t>(mask_bits >> 24)};
  std::vector<std::uint8_t> frame;
  frame.reserve(size + 14);
  AppendClientFrame(opcode, payload, size, mask, frame);
  try {
    socket_.SendAll(frame.data(), frame.size(), deadline);
  } catch (const ConnectionLost&) {
    open_ = false;
    throw;
  }
}

void WebSocketClient::SendBinary(const std::vector<std::uint8_t>& payload, Deadline deadline) {
  if (!open_) throw ConnectionLost("websocket to " + socket_.peer() + " is closed", kAbnormalClosure);
  SendFrame(Opcode::kBinary, payload.data(), payload.size(), deadline);
}

bool WebSocketClient::ReadEvent(Deadline deadline, bool wait, WebSocketEvent& event) {
  try {
    while (true) {
      if (std::optional<WebSocketEvent> next = reader_.Next()) {
        event = std::move(*next);
        return true;
      }
      if (!wait && !socket_.Readable()) return false;
      const std::size_t count = socket_.ReceiveSome(receive_buffer_.data(), receive_buffer_.size(), deadline);
      if (count == 0) {
        throw ConnectionLost("policy server " + socket_.peer() + " dropped the connection without a close frame",
                             kAbnormalClosure);
      }
      reader_.Append(receive_buffer_.data(), count);
    }
  } catch (const ConnectionLost&) {
    open_ = false;
    throw;
  } catch (const WebSocketProtocolError&) {
    open_ = false;
    throw;
  }
}

std::optional<WebSocketMessage> WebSocketClient::Handle(WebSocketEvent& event) {
  switch (event.kind) {
    case WebSocketEvent::Kind::kText:
    case WebSocketEvent::Kind::kBinary:
      return WebSocketMessage{event.kind == WebSocketEvent::Kind::kText, std::move(event.payload)};
    case WebSocketEvent::Kind::kPing:
      SendFrame(Opcode::kPong, event.payload.data(), event.payload.size(), Clock::now() + kControlSendTime);
      return std::nullopt;
    case WebSocketEvent::Kind::kPong: return std::nullopt;
    case WebSocketEvent::Kind::kClose: break;
  }
  if (open_) {
    // Echo the status (section 5.5.1); a close without one is answered without one.
    std::vector<std::uint8_t> status;
    if (event.close_code != kNoStatusReceived)
      status = {static_cast<std::uint8_t>(event.close_code >> 8), static_cast<std::uint8_t>(event.close_code & 0xff)};
    try {
      SendFrame(Opcode::kClose, status.data(), status.size(), Clock::now() + kControlSendTime);
    } catch (const ConnectionLost&) {
      // The server may drop the TCP connection right after its close frame.
    }
    open_ = false;
  }
  throw ConnectionLost("policy server " + socket_.peer() + " closed the connection (" +
                           CloseDescription(event.close_code, event.payload) + ")",
                       event.close_code, std::string(event.payload.begin(), event.payload.end()));
}

WebSocketMessage WebSocketClient::Receive(Deadline deadline) {
  if (!pending_.empty()) {
    WebSocketMessage message = std::move(pending_.front());
    pending_.pop_front();
    return message;
  }
  if (!open_) throw ConnectionLost("websocket to " + socket_.peer() + " is closed", kAbnormalClosure);
  while (true) {
    WebSocketEvent event;
    ReadEvent(deadline, true, event);
    if (std::optional<WebSocketMessage> message = Handle(event)) return std::move(*message);
  }
}

bool WebSocketClient::ServicePending() {
  if (!open_) return false;
  try {
    WebSocketEvent event;
    while (ReadEvent(Clock::now(), false, event)) {
      if (std::optional<WebSocketMessage> message = Handle(event)) pending_.push_back(std::move(*message));
    }
  } catch (const ConnectionLost&) {
    return false;
  }
  return open_;
}

}  // namespace tavis::batch::remote
