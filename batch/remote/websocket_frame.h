// The RFC 6455 frame format, both directions of a client: building masked client frames and
// parsing the server's unmasked ones. No sockets here, so the parser can be fed any bytes.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace tavis::batch::remote {

enum class Opcode : std::uint8_t {
  kContinuation = 0x0,
  kText = 0x1,
  kBinary = 0x2,
  kClose = 0x8,
  kPing = 0x9,
  kPong = 0xA,
};

struct Frame {
  bool fin = true;
  Opcode opcode = Opcode::kBinary;
  std::vector<std::uint8_t> payload;
};

// Appends a client frame: FIN set, MASK set with `mask`, the payload XOR-masked, its length in
// the shortest of the 7-bit, 16-bit and 64-bit forms (section 5.2).
void AppendClientFrame(Opcode opcode, const std::uint8_t* payload, std::size_t size,
                       const std::array<std::uint8_t, 4>& mask, std::vector<std::uint8_t>& out);

// Parses the server frame at the front of [data, data + size). Returns the bytes it spans, or 0
// when they have not all arrived yet (nothing is allocated for a length not yet backed by bytes).
// Throws WebSocketProtocolError naming the fault and `stream_offset` (where `data` starts in the
// stream) for: reserved bits (no extension was negotiated), an unknown opcode, a masked frame
// (servers must not mask), a fragmented or over-125-byte control frame, a 64-bit length with
// the top bit set, or a payload over `max_payload` bytes. Non-shortest lengths are accepted.
std::size_t ParseServerFrame(const std::uint8_t* data, std::size_t size, std::uint64_t max_payload,
                             std::uint64_t stream_offset, Frame& frame);

}  // namespace tavis::batch::remote
