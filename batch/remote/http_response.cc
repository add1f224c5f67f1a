#include "batch/remote/http_response.h"

#include <algorithm>
#include <array>
#include <cctype>

#include "batch/remote/remote_error.h"

namespace tavis::batch::remote {
namespace {

constexpr std::size_t kMaxHeadBytes = 16 * 1024;

std::string Lower(std::string_view text) {
  std::string lower(text);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  return lower;
}

std::string_view Trim(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
  return text;
}

}  // namespace

std::optional<std::string> HttpResponseHead::Header(std::string_view name) const {
  const std::string wanted = Lower(name);
  for (const auto& [header, value] : headers) {
    if (header == wanted) return value;
  }
  return std::nullopt;
}

HttpResponseHead ParseHttpResponseHead(std::string_view head) {
  HttpResponseHead parsed;
  std::size_t line_start = 0;
  bool first = true;
  while (line_start < head.size()) {
    std::size_t line_end = head.find("\r\n", line_start);
    if (line_end == std::string_view::npos) line_end = head.size();
    const std::string_view line = head.substr(line_start, line_end - line_start);
    line_start = line_end + 2;
    if (first) {
      first = false;
      const bool digits = line.size() >= 12 && std::all_of(line.begin() + 9, line.begin() + 12,
                                                           [](unsigned char c) { return std::isdigit(c); });
      if (line.rfind("HTTP/1.", 0) != 0 || !digits || line[8] != ' ') {
        throw WebSocketProtocolError("not an HTTP response status line: '" + std::string(line.substr(0, 80)) + "'");
      }
      parsed.status = std::stoi(std::string(line.substr(9, 3)));
      parsed.reason = std::string(Trim(line.substr(12)));
      continue;
    }
    const std::size_t colon = line.find(':');
    if (colon == std::string_view::npos || colon == 0) {
      throw WebSocketProtocolError("malformed HTTP header line: '" + std::string(line.substr(0, 80)) + "'");
    }
    parsed.headers.emplace_back(Lower(line.substr(0, colon)), std::string(Trim(line.substr(colon + 1))));
  }
  if (first) throw WebSocketProtocolError("empty HTTP response");
  return parsed;
}

HttpResponseStart ReadHttpResponseStart(TcpSocket& socket, Deadline deadline) {
  std::string received;
  std::array<std::uint8_t, 4096> chunk{};
  while (true) {
    const std::size_t end = received.find("\r\n\r\n");
    if (end != std::string::npos) {
      HttpResponseStart start{ParseHttpResponseHead(std::string_view(received).substr(0, end)), {}};
      start.rest.assign(received.begin() + static_cast<std::ptrdiff_t>(end + 4), received.end());
      return start;
    }
    if (received.size() > kMaxHeadBytes) {
      throw WebSocketProtocolError("HTTP response head from " + socket.peer() + " exceeds 16 KiB");
    }
    const std::size_t count = socket.ReceiveSome(chunk.data(), chunk.size(), deadline);
    if (count == 0) {
      throw ConnectionLost("policy server " + socket.peer() + " closed the connection before an HTTP response" +
                               (received.empty() ? "" : " was complete"),
                           1006);
    }
    received.append(reinterpret_cast<const char*>(chunk.data()), count);
  }
}

}  // namespace tavis::batch::remote
