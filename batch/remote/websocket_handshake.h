// The client's half of the RFC 6455 opening handshake (section 4): the upgrade request and the
// check of the server's 101 answer. SHA-1, base64 and the random key come from OpenSSL's
// libcrypto rather than code of our own.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "batch/remote/http_response.h"
#include "batch/remote/websocket_url.h"

namespace tavis::batch::remote {

// base64 of 16 random bytes, a fresh Sec-WebSocket-Key.
std::string MakeWebSocketKey();

// base64(SHA-1(key + "258EAFA5-E914-47DA-95CA-C5AB0DC85B11")), the Sec-WebSocket-Accept a server
// must answer `key` with.
std::string ComputeWebSocketAccept(std::string_view key);

// "GET <path> HTTP/1.1" with Host, Upgrade, Connection, Sec-WebSocket-Key/-Version and no
// extensions (openpi runs with compression=None); `extra_headers` are "Name: value" lines,
// e.g. openpi's "Authorization: Api-Key <key>".
std::string BuildUpgradeRequest(const WebSocketUrl& url, std::string_view key,
                                const std::vector<std::string>& extra_headers = {});

// Throws WebSocketProtocolError naming the bad value unless the response is 101 with
// "Upgrade: websocket", a "Connection" containing "upgrade", the Sec-WebSocket-Accept for `key`,
// and no extension we did not ask for.
void CheckUpgradeResponse(const HttpResponseHead& response, std::string_view key);

}  // namespace tavis::batch::remote
