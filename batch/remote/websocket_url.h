// "ws://host[:port][/path]" split into its parts; the policy server's address.
#pragma once

#include <string>

namespace tavis::batch::remote {

struct WebSocketUrl {
  std::string host;  // a name, an IPv4 address, or an IPv6 address without its brackets
  int port = 80;
  std::string path = "/";

  // "host:port" as it goes in the Host header and in error messages.
  std::string Authority() const;
};

// Throws std::invalid_argument naming the URL when the scheme is not ws:// (wss:// needs TLS,
// which this client does not do), it holds more than one URL, the host is empty or holds a
// character no host name has (an IPv6 address must be in brackets), or the port is not 1-65535.
WebSocketUrl ParseWebSocketUrl(const std::string& url);

}  // namespace tavis::batch::remote
