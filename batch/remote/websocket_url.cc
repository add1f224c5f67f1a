#include "batch/remote/websocket_url.h"

#include <stdexcept>

namespace tavis::batch::remote {
namespace {

// What a host name or an IPv4 address is written with (an IPv6 address is in brackets).
constexpr const char* kHostNameCharacters = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789.-_";

}  // namespace

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
  // Two servers pasted into one value ("ws://a:1,ws://b:2", "ws://a:1ws://b:2") would otherwise
  // read as an odd host or port, or even as one server.
  if (url.find("ws://", scheme.size()) != std::string::npos || url.find("wss://", scheme.size()) != std::string::npos)
    throw bad("holds more than one URL (one server per URL)");
  WebSocketUrl parsed;
  const std::size_t path_start = url.find('/', scheme.size());
  std::string authority =
      url.substr(scheme.size(), path_start == std::string::npos ? std::string::npos : path_start - scheme.size());
  if (path_start != std::string::npos) parsed.path = url.substr(path_start);

  std::string port_text;
  const bool bracketed = !authority.empty() && authority[0] == '[';
  if (bracketed) {
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
  if (!bracketed) {
    const std::size_t odd = parsed.host.find_first_not_of(kHostNameCharacters);
    if (odd != std::string::npos) {
      // A comma says what went wrong (two servers in one) better than a colon before it.
      const char c = parsed.host.find(',') != std::string::npos ? ',' : parsed.host[odd];
      throw bad("host '" + parsed.host + "' holds '" + std::string(1, c) + "', which no host name has" +
                (c == ':'   ? " (an IPv6 address goes in brackets: ws://[::1]:8000)"
                 : c == ',' ? " (one server per URL)"
                            : ""));
    }
  }
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
