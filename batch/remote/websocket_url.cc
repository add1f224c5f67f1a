#include "batch/remote/websocket_url.h"

#include <stdexcept>

namespace tavis::batch::remote {

std::string WebSocketUrl::Authority() const {
  const bool ipv6 = host.find(':') != std::string::npos;
  return (ipv6 ? "[" + host + "]" : host) + ":" + std::to_string(port);
}

WebSocketUrl ParseWebSocketUrl(const std::string& url) {
  const auto bad = [&url](const std::string& why) {
    return std::invalid_argument("policy server URL '" + url + "': " + why);
  };
  const std::string scheme = "ws://";
  if (url.rfind("wss://", 0) == 0) throw bad("wss:// (TLS) is not supported; use ws://");
  if (url.rfind(scheme, 0) != 0) throw bad("expected ws://HOST:PORT");
  WebSocketUrl parsed;
  const std::size_t path_start = url.find('/', scheme.size());
  std::string authority =
      url.substr(scheme.size(), path_start == std::string::npos ? std::string::npos : path_start - scheme.size());
  if (path_start != std::string::npos) parsed.path = url.substr(path_start);

  std::string port_text;
  if (!authority.empty() && authority[0] == '[') {
    const std::size_t close = authority.find(']');
    if (close == std::string::npos) throw bad("unterminated IPv6 address");
    parsed.host = authority.substr(1, close - 1);
    if (close + 1 < authority.size()) {
      if (authority[close + 1] != ':') throw bad("expected ':' after the IPv6 address");
      port_text = authority.substr(close + 2);
    }
  } else {
    const std::size_t colon = authority.rfind(':');
    parsed.host = authority.substr(0, colon);
    if (colon != std::string::npos) port_text = authority.substr(colon + 1);
  }
  if (parsed.host.empty()) throw bad("empty host");
  if (!port_text.empty() || authority.back() == ':') {
    if (port_text.empty() || port_text.size() > 5 || port_text.find_first_not_of("0123456789") != std::string::npos) {
      throw bad("port '" + port_text + "' is not a number");
    }
    parsed.port = std::stoi(port_text);
    if (parsed.port < 1 || parsed.port > 65535) throw bad("port " + port_text + " is not in 1-65535");
  }
  return parsed;
}

}  // namespace tavis::batch::remote
