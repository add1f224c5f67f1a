#include "batch/remote/websocket_handshake.h"

#include <openssl/evp.h>
#include <openssl/rand.h>

#include <algorithm>
#include <array>
#include <cctype>

#include "batch/remote/remote_error.h"

namespace tavis::batch::remote {
namespace {

constexpr std::string_view kAcceptGuid = "258EAFA5-E914-47DA-95CA-C5AB0DC85B11";

std::string Base64(const unsigned char* data, std::size_t size) {
  std::string text(4 * ((size + 2) / 3) + 1, '\0');  // +1: EVP_EncodeBlock writes a NUL
  const int length = EVP_EncodeBlock(reinterpret_cast<unsigned char*>(text.data()), data, static_cast<int>(size));
  text.resize(static_cast<std::size_t>(length));
  return text;
}

bool ContainsToken(std::string value, std::string_view token) {
  std::transform(value.begin(), value.end(), value.begin(), [](unsigned char c) { return std::tolower(c); });
  return value.find(token) != std::string::npos;
}

}  // namespace

std::string MakeWebSocketKey() {
  std::array<unsigned char, 16> nonce{};
  if (RAND_bytes(nonce.data(), static_cast<int>(nonce.size())) != 1) {
    throw std::runtime_error("OpenSSL RAND_bytes failed to make a websocket key");
  }
  return Base64(nonce.data(), nonce.size());
}

std::string ComputeWebSocketAccept(std::string_view key) {
  const std::string input = std::string(key) + std::string(kAcceptGuid);
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int digest_size = 0;
  if (EVP_Digest(input.data(), input.size(), digest.data(), &digest_size, EVP_sha1(), nullptr) != 1) {
    throw std::runtime_error("OpenSSL EVP_Digest(SHA-1) failed");
  }
  return Base64(digest.data(), digest_size);
}

std::string BuildUpgradeRequest(const WebSocketUrl& url, std::string_view key,
                                const std::vector<std::string>& extra_headers) {
  std::string request = "GET " + url.path + " HTTP/1.1\r\nHost: " + url.Authority() +
                        "\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Key: " + std::string(key) +
                        "\r\nSec-WebSocket-Version: 13\r\n";
  for (const std::string& header : extra_headers) request += header + "\r\n";
  return request + "\r\n";
}

void CheckUpgradeResponse(const HttpResponseHead& response, std::string_view key) {
  if (response.status != 101) {
    throw WebSocketProtocolError("websocket upgrade refused: HTTP " + std::to_string(response.status) + " " +
                                 response.reason + " (expected 101 Switching Protocols)");
  }
  const std::string upgrade = response.Header("Upgrade").value_or("");
  if (!ContainsToken(upgrade, "websocket")) {
    throw WebSocketProtocolError("websocket upgrade answered with Upgrade: '" + upgrade + "'");
  }
  const std::string connection = response.Header("Connection").value_or("");
  if (!ContainsToken(connection, "upgrade")) {
    throw WebSocketProtocolError("websocket upgrade answered with Connection: '" + connection + "'");
  }
  const std::string accept = response.Header("Sec-WebSocket-Accept").value_or("");
  const std::string expected = ComputeWebSocketAccept(key);
  if (accept != expected) {
    throw WebSocketProtocolError("websocket upgrade answered with Sec-WebSocket-Accept '" + accept + "', expected '" +
                                 expected + "'");
  }
  if (const auto extensions = response.Header("Sec-WebSocket-Extensions")) {
    throw WebSocketProtocolError("websocket server chose extensions '" + *extensions + "' that were not offered");
  }
}

}  // namespace tavis::batch::remote
