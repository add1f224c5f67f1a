// The websocket pieces that need no server, against the examples printed in RFC 6455 (sections
// 1.3 and 5.7), which we did not write.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "batch/remote/http_response.h"
#include "batch/remote/remote_error.h"
#include "batch/remote/websocket_frame.h"
#include "batch/remote/websocket_handshake.h"
#include "batch/remote/websocket_reader.h"
#include "batch/remote/websocket_url.h"

namespace tavis::batch::remote {
namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes Text(const std::string& text) { return Bytes(text.begin(), text.end()); }

Bytes ClientFrame(Opcode opcode, const Bytes& payload, std::array<std::uint8_t, 4> mask) {
  Bytes frame;
  AppendClientFrame(opcode, payload.data(), payload.size(), mask, frame);
  return frame;
}

// Feeds `stream` one byte at a time (the worst split) and collects every event.
std::vector<WebSocketEvent> ReadAll(const Bytes& stream, std::uint64_t max_message = 1 << 20) {
  WebSocketReader reader(max_message);
  std::vector<WebSocketEvent> events;
  for (const std::uint8_t byte : stream) {
    reader.Append(&byte, 1);
    while (std::optional<WebSocketEvent> event = reader.Next()) events.push_back(std::move(*event));
  }
  return events;
}

std::string ReaderError(const Bytes& stream, std::uint64_t max_message = 1 << 20) {
  try {
    ReadAll(stream, max_message);
  } catch (const WebSocketProtocolError& error) {
    return error.what();
  }
  return "no error";
}

TEST(WebSocketFrame, MaskedClientFrameMatchesRfcExample) {
  // RFC 6455 5.7: "A single-frame masked text message ... contains 'Hello'".
  EXPECT_EQ(ClientFrame(Opcode::kText, Text("Hello"), {0x37, 0xfa, 0x21, 0x3d}),
            (Bytes{0x81, 0x85, 0x37, 0xfa, 0x21, 0x3d, 0x7f, 0x9f, 0x4d, 0x51, 0x58}));
}

TEST(WebSocketFrame, ClientFramesUseTheShortestLengthForm) {
  const Bytes medium = ClientFrame(Opcode::kBinary, Bytes(256, 0), {0, 0, 0, 0});  // RFC 5.7: 7E 0100
  EXPECT_EQ(Bytes(medium.begin(), medium.begin() + 4), (Bytes{0x82, 0xfe, 0x01, 0x00}));
  EXPECT_EQ(medium.size(), 4U + 4U + 256U);
  const Bytes large = ClientFrame(Opcode::kBinary, Bytes(65536, 0), {0, 0, 0, 0});  // RFC 5.7: 7F 0..010000
  EXPECT_EQ(Bytes(large.begin(), large.begin() + 10), (Bytes{0x82, 0xff, 0, 0, 0, 0, 0, 1, 0, 0}));
  EXPECT_EQ(ClientFrame(Opcode::kBinary, Bytes(125, 0), {0, 0, 0, 0})[1], 0x80 | 125);
}

TEST(WebSocketFrame, MasksEveryPayloadByteWithTheKeyCycle) {
  Bytes payload(301);
  for (std::size_t i = 0; i < payload.size(); ++i) payload[i] = static_cast<std::uint8_t>(i * 7);
  const std::array<std::uint8_t, 4> mask = {0x12, 0x34, 0x56, 0x78};
  const Bytes frame = ClientFrame(Opcode::kBinary, payload, mask);
  ASSERT_EQ(frame.size(), 4U + 4U + payload.size());
  EXPECT_EQ(Bytes(frame.begin() + 4, frame.begin() + 8), Bytes(mask.begin(), mask.end()));
  for (std::size_t i = 0; i < payload.size(); ++i) {
    ASSERT_EQ(frame[8 + i], payload[i] ^ mask[i % 4]) << "byte " << i;
  }
}

TEST(WebSocketReader, ReadsRfcServerExamplesSplitAnywhere) {
  Bytes stream = {0x81, 0x05, 'H', 'e', 'l', 'l', 'o'};                        // unmasked text
  const Bytes fragmented = {0x01, 0x03, 'H', 'e', 'l', 0x80, 0x02, 'l', 'o'};  // text in two fragments
  const Bytes ping = {0x89, 0x05, 'H', 'e', 'l', 'l', 'o'};
  Bytes binary = {0x82, 0x7e, 0x01, 0x00};  // 256 bytes, 16-bit length
  binary.resize(4 + 256, 0xab);
  for (const Bytes* part : std::initializer_list<const Bytes*>{&fragmented, &ping, &binary})
    stream.insert(stream.end(), part->begin(), part->end());
  const std::vector<WebSocketEvent> events = ReadAll(stream);
  ASSERT_EQ(events.size(), 4U);
  EXPECT_EQ(events[0].kind, WebSocketEvent::Kind::kText);
  EXPECT_EQ(events[0].payload, Text("Hello"));
  EXPECT_EQ(events[1].kind, WebSocketEvent::Kind::kText);
  EXPECT_EQ(events[1].payload, Text("Hello"));
  EXPECT_EQ(events[2].kind, WebSocketEvent::Kind::kPing);
  EXPECT_EQ(events[2].payload, Text("Hello"));
  EXPECT_EQ(events[3].kind, WebSocketEvent::Kind::kBinary);
  EXPECT_EQ(events[3].payload, Bytes(256, 0xab));
}

TEST(WebSocketReader, ReadsAPingBetweenFragmentsAndA64BitLength) {
  Bytes stream = {0x02, 0x01, 0x07, 0x89, 0x00, 0x80, 0x7f, 0, 0, 0, 0, 0, 0x10, 0, 0};  // then 1 MiB
  stream.resize(stream.size() + (1 << 20), 0x05);
  const std::vector<WebSocketEvent> events = ReadAll(stream, 2 << 20);
  ASSERT_EQ(events.size(), 2U);
  EXPECT_EQ(events[0].kind, WebSocketEvent::Kind::kPing);
  EXPECT_EQ(events[1].kind, WebSocketEvent::Kind::kBinary);
  EXPECT_EQ(events[1].payload.size(), 1U + (1 << 20));
  EXPECT_EQ(events[1].payload[0], 0x07);
  EXPECT_EQ(events[1].payload.back(), 0x05);
}

TEST(WebSocketReader, CloseCarriesCodeAndReason) {
  const Bytes close = {0x88, 0x06, 0x03, 0xf3, 'o', 'o', 'p', 's'};  // 1011 "oops"
  const std::vector<WebSocketEvent> events = ReadAll(close);
  ASSERT_EQ(events.size(), 1U);
  EXPECT_EQ(events[0].kind, WebSocketEvent::Kind::kClose);
  EXPECT_EQ(events[0].close_code, 1011);
  EXPECT_EQ(events[0].payload, Text("oops"));
  EXPECT_EQ(ReadAll({0x88, 0x00})[0].close_code, 1005);
}

TEST(WebSocketReader, RejectsWhatRfc6455Forbids) {
  EXPECT_EQ(ReaderError({0x82, 0x81, 1, 2, 3, 4, 0}), "websocket frame at stream byte 0: masked frame from the server");
  EXPECT_EQ(ReaderError({0xc2, 0x00}), "websocket frame at stream byte 0: reserved bits 0x4 set without an extension");
  EXPECT_EQ(ReaderError({0x83, 0x00}), "websocket frame at stream byte 0: unknown opcode 3");
  EXPECT_EQ(ReaderError({0x09, 0x00}), "websocket frame at stream byte 0: fragmented control frame (opcode 9)");
  EXPECT_EQ(ReaderError({0x89, 0x7e, 0x00, 0x7e}),
            "websocket frame at stream byte 0: control frame payload of 126 bytes (limit 125)");
  EXPECT_EQ(ReaderError({0x82, 0x00, 0x80, 0x00}),
            "websocket continuation frame at stream byte 2 with no fragmented message open");
  EXPECT_EQ(ReaderError({0x02, 0x00, 0x82, 0x00}),
            "websocket data frame at stream byte 2 while a fragmented message is still open");
  EXPECT_EQ(ReaderError({0x88, 0x01, 0x03}),
            "websocket close frame at stream byte 0 has a 1-byte payload (a status code needs 2)");
  EXPECT_EQ(ReaderError({0x82, 0x7f, 0x80, 0, 0, 0, 0, 0, 0, 0}),
            "websocket frame at stream byte 0: 64-bit length with the top bit set");
  EXPECT_EQ(ReaderError({0x02, 0x02, 0, 0, 0x80, 0x02, 0, 0}, 3),
            "websocket frame at stream byte 4: payload of 2 bytes over the limit of 1");
}

TEST(WebSocketHandshake, AcceptKeyMatchesRfcExample) {
  // RFC 6455 section 1.3.
  EXPECT_EQ(ComputeWebSocketAccept("dGhlIHNhbXBsZSBub25jZQ=="), "s3pPLMBiTxaQ9kYGzzhZRbK+xOo=");
  const std::string key = MakeWebSocketKey();
  EXPECT_EQ(key.size(), 24U);  // base64 of 16 bytes
  EXPECT_NE(key, MakeWebSocketKey());
}

TEST(WebSocketHandshake, RequestAndResponseCheck) {
  const std::string request =
      BuildUpgradeRequest(ParseWebSocketUrl("ws://example:8000"), "KEY", {"Authorization: Api-Key s"});
  EXPECT_EQ(request,
            "GET / HTTP/1.1\r\nHost: example:8000\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
            "Sec-WebSocket-Key: KEY\r\nSec-WebSocket-Version: 13\r\nAuthorization: Api-Key s\r\n\r\n");
  const std::string key = "dGhlIHNhbXBsZSBub25jZQ==";
  EXPECT_NO_THROW(CheckUpgradeResponse(
      ParseHttpResponseHead("HTTP/1.1 101 Switching Protocols\r\nupgrade: WebSocket\r\n"
                            "Connection: upgrade\r\nSec-WebSocket-Accept: s3pPLMBiTxaQ9kYGzzhZRbK+xOo="),
      key));
  try {
    CheckUpgradeResponse(ParseHttpResponseHead("HTTP/1.1 101 OK\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                                               "Sec-WebSocket-Accept: wrong"),
                         key);
    FAIL() << "no error";
  } catch (const WebSocketProtocolError& error) {
    EXPECT_STREQ(
        error.what(),
        "websocket upgrade answered with Sec-WebSocket-Accept 'wrong', expected 's3pPLMBiTxaQ9kYGzzhZRbK+xOo='");
  }
  try {
    CheckUpgradeResponse(ParseHttpResponseHead("HTTP/1.1 426 Upgrade Required\r\nContent-Length: 0"), key);
    FAIL() << "no error";
  } catch (const WebSocketProtocolError& error) {
    EXPECT_STREQ(error.what(),
                 "websocket upgrade refused: HTTP 426 Upgrade Required (expected 101 Switching Protocols)");
  }
  EXPECT_THROW(ParseHttpResponseHead("SSH-2.0-OpenSSH"), WebSocketProtocolError);
}

TEST(WebSocketUrl, ParsesHostPortAndPath) {
  const WebSocketUrl url = ParseWebSocketUrl("ws://gpu-box:8000");
  EXPECT_EQ(url.host, "gpu-box");
  EXPECT_EQ(url.port, 8000);
  EXPECT_EQ(url.path, "/");
  const WebSocketUrl ipv6 = ParseWebSocketUrl("ws://[::1]:9000/v1/realtime");
  EXPECT_EQ(ipv6.host, "::1");
  EXPECT_EQ(ipv6.path, "/v1/realtime");
  EXPECT_EQ(ipv6.Authority(), "[::1]:9000");
  EXPECT_EQ(ParseWebSocketUrl("ws://host").port, 80);
  try {
    ParseWebSocketUrl("wss://host:443");
    FAIL() << "no error";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "policy server URL 'wss://host:443': wss:// (TLS) is not supported; use ws://");
  }
  EXPECT_THROW(ParseWebSocketUrl("http://host:8000"), std::invalid_argument);
  EXPECT_THROW(ParseWebSocketUrl("ws://host:0"), std::invalid_argument);
  EXPECT_THROW(ParseWebSocketUrl("ws://host:80x"), std::invalid_argument);
  EXPECT_THROW(ParseWebSocketUrl("ws://:80"), std::invalid_argument);
}

// Two servers pasted into one value are named, not read as a host "a:1,ws" with an empty port,
// or as one server "a:1,b" on port 2. Several servers are several URLs (--server repeated).
TEST(WebSocketUrl, RefusesTwoUrlsInOneAndHostsNoHostNameHas) {
  const auto message = [](const std::string& url) {
    try {
      ParseWebSocketUrl(url);
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message("ws://a:1,ws://b:2"),
            "policy server URL 'ws://a:1,ws://b:2': holds more than one URL (one server per URL)");
  EXPECT_EQ(message("ws://a:1ws://b:2"),
            "policy server URL 'ws://a:1ws://b:2': holds more than one URL (one server per URL)");
  EXPECT_EQ(message("ws://a:1 ws://b:2/x"),
            "policy server URL 'ws://a:1 ws://b:2/x': holds more than one URL (one server per URL)");
  EXPECT_EQ(message("ws://a:1,b:2"),
            "policy server URL 'ws://a:1,b:2': host 'a:1,b' holds ',', which no host name has (one server per URL)");
  EXPECT_EQ(message("ws://fe80::1:80"),
            "policy server URL 'ws://fe80::1:80': host 'fe80::1' holds ':', which no host "
            "name has (an IPv6 address goes in brackets: ws://[::1]:8000)");
  EXPECT_EQ(message("ws://a,b:2"),
            "policy server URL 'ws://a,b:2': host 'a,b' holds ',', which no host name has (one "
            "server per URL)");
  EXPECT_EQ(message("ws://::1"),
            "policy server URL 'ws://::1': host ':' holds ':', which no host name has (an IPv6 "
            "address goes in brackets: ws://[::1]:8000)");
  EXPECT_EQ(message("ws://a b:2"), "policy server URL 'ws://a b:2': host 'a b' holds ' ', which no host name has");
  EXPECT_EQ(ParseWebSocketUrl("ws://gpu_box-1.local:8000/a://b").path, "/a://b") << "a path may hold anything";
  EXPECT_EQ(ParseWebSocketUrl("ws://10.0.0.7:8000").host, "10.0.0.7");
}

}  // namespace
}  // namespace tavis::batch::remote
