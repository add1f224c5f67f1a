#include "batch/remote/openpi_session.h"

#include <stdexcept>

#include "batch/remote/msgpack_decoder.h"
#include "batch/remote/msgpack_encoder.h"
#include "batch/remote/remote_error.h"

namespace tavis::batch::remote {
namespace {

// After the traceback, how long to wait for the close frame that carries the status code.
constexpr auto kCloseAfterErrorTime = std::chrono::seconds(2);

double MillisecondsBetween(Clock::time_point start, Clock::time_point end) {
  return std::chrono::duration<double, std::milli>(end - start).count();
}

}  // namespace

OpenpiSession::OpenpiSession(OpenpiSessionOptions options)
    : options_(std::move(options)), url_(ParseWebSocketUrl(options_.url)) {
  Connect();
}

void OpenpiSession::Connect() {
  client_.reset();
  ++connections_;
  std::vector<std::string> headers;
  if (options_.api_key) headers.push_back("Authorization: Api-Key " + *options_.api_key);
  const Deadline deadline = Clock::now() + options_.connect_timeout;
  client_ = std::make_unique<WebSocketClient>(url_, deadline, headers, options_.max_reply_bytes);
  metadata_ = DecodeMsgpack(ReceiveBinary(deadline));
}

std::vector<std::uint8_t> OpenpiSession::ReceiveBinary(Deadline deadline) {
  WebSocketMessage message = client_->Receive(deadline);
  if (!message.text) return std::move(message.payload);
  const std::string traceback(message.payload.begin(), message.payload.end());
  try {
    client_->Receive(Clock::now() + kCloseAfterErrorTime);
  } catch (const ConnectionLost& closed) {
    throw PolicyServerError(traceback, closed.close_code(), closed.close_reason());
  } catch (const std::runtime_error&) {
    // No close frame followed in time; the traceback is the error all the same.
  }
  throw PolicyServerError(traceback, 0, "no close frame followed the traceback");
}

InferResult OpenpiSession::Infer(const Value& observation) {
  if (!observation.is<Value::Map>()) {
    throw std::invalid_argument("openpi observation must be a map, got " + observation.TypeName());
  }
  const std::vector<std::uint8_t> request = EncodeMsgpack(observation);
  bool reconnected = false;
  if (!client_ || !client_->ServicePending()) {
    Connect();
    reconnected = true;
  }
  while (true) {
    const Clock::time_point start = Clock::now();
    const Deadline deadline = start + options_.reply_timeout;
    try {
      client_->SendBinary(request, deadline);
      std::vector<std::uint8_t> reply_bytes = ReceiveBinary(deadline);
      const Clock::time_point end = Clock::now();
      Value reply;
      try {
        reply = DecodeMsgpack(reply_bytes);
      } catch (const MsgpackError& error) {
        throw MalformedReply(std::string("malformed reply: ") + error.what());
      } catch (const std::invalid_argument& error) {
        throw MalformedReply(std::string("malformed reply: ") + error.what());
      }
      if (!reply.is<Value::Map>()) throw MalformedReply("openpi reply must be a map, got " + reply.TypeName());
      return {std::move(reply), MillisecondsBetween(start, end), reconnected};
    } catch (const MessageTooLarge& error) {
      client_.reset();  // the rest of the oversize reply is still on the wire: the next request reconnects
      throw MalformedReply("reply over the limit of " + std::to_string(options_.max_reply_bytes) +
                           " bytes (the max_reply_mb setting): " + error.what());
    } catch (const ConnectionLost&) {
      if (reconnected) throw;
    } catch (const RemoteTimeout&) {
      client_.reset();  // its late reply would answer the next request: start that one afresh
      throw;
    }
    Connect();
    reconnected = true;
  }
}

void OpenpiSession::ServiceKeepalive() {
  if (!client_ || !client_->ServicePending()) Connect();
}

}  // namespace tavis::batch::remote
