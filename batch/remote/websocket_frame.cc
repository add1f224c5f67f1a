#include "batch/remote/websocket_frame.h"

#include <cstring>
#include <string>

#include "batch/remote/remote_error.h"

namespace tavis::batch::remote {
namespace {

constexpr std::uint8_t kFinBit = 0x80;
constexpr std::uint8_t kReservedBits = 0x70;
constexpr std::uint8_t kMaskBit = 0x80;
constexpr std::size_t kMaxControlPayload = 125;

bool IsKnownOpcode(std::uint8_t opcode) { return opcode <= 0x2 || (opcode >= 0x8 && opcode <= 0xA); }

WebSocketProtocolError FrameError(const std::string& what, std::uint64_t offset) {
  return WebSocketProtocolError("websocket frame at stream byte " + std::to_string(offset) + ": " + what);
}

}  // namespace

void AppendClientFrame(Opcode opcode, const std::uint8_t* payload, std::size_t size,
                       const std::array<std::uint8_t, 4>& mask, std::vector<std::uint8_t>& out) {
  out.push_back(static_cast<std::uint8_t>(kFinBit | static_cast<std::uint8_t>(opcode)));
  if (size <= 125) {
    out.push_back(static_cast<std::uint8_t>(kMaskBit | size));
  } else if (size <= 0xffff) {
    out.push_back(kMaskBit | 126);
    for (int shift = 8; shift >= 0; shift -= 8) out.push_back(static_cast<std::uint8_t>(size >> shift));
  } else {
    out.push_back(kMaskBit | 127);
    for (int shift = 56; shift >= 0; shift -= 8)
      out.push_back(static_cast<std::uint8_t>(static_cast<std::uint64_t>(size) >> shift));
  }
  out.insert(out.end(), mask.begin(), mask.end());
  const std::size_t start = out.size();
  out.resize(start + size);
  // Eight bytes at a time: requests carry megabytes of images, and byte-wise XOR costs ms.
  std::uint64_t wide_mask = 0;
  for (std::size_t i = 0; i < sizeof wide_mask; ++i) reinterpret_cast<std::uint8_t*>(&wide_mask)[i] = mask[i % 4];
  std::size_t i = 0;
  for (; i + sizeof wide_mask <= size; i += sizeof wide_mask) {
    std::uint64_t word;
    std::memcpy(&word, payload + i, sizeof word);
    word ^= wide_mask;
    std::memcpy(out.data() + start + i, &word, sizeof word);
  }
  for (; i < size; ++i) out[start + i] = payload[i] ^ mask[i % 4];
}

std::size_t ParseServerFrame(const std::uint8_t* data, std::size_t size, std::uint64_t max_payload,
                             std::uint64_t stream_offset, Frame& frame) {
  if (size < 2) return 0;
  const std::uint8_t first = data[0];
  const std::uint8_t second = data[1];
  const auto opcode = static_cast<std::uint8_t>(first & 0x0f);
  if ((first & kReservedBits) != 0) {
    throw FrameError("reserved bits 0x" + std::to_string((first & kReservedBits) >> 4) + " set without an extension",
                     stream_offset);
  }
  if (!IsKnownOpcode(opcode)) throw FrameError("unknown opcode " + std::to_string(opcode), stream_offset);
  if ((second & kMaskBit) != 0) throw FrameError("masked frame from the server", stream_offset);
  const bool fin = (first & kFinBit) != 0;
  const bool control = opcode >= 0x8;
  if (control && !fin)
    throw FrameError("fragmented control frame (opcode " + std::to_string(opcode) + ")", stream_offset);

  std::uint64_t length = second & 0x7f;
  std::size_t header = 2;
  if (length >= 126) {
    const std::size_t extra = length == 126 ? 2 : 8;
    if (size < header + extra) return 0;
    std::uint64_t extended = 0;
    for (std::size_t i = 0; i < extra; ++i) extended = (extended << 8) | data[header + i];
    header += extra;
    if (extra == 8 && (extended >> 63) != 0) throw FrameError("64-bit length with the top bit set", stream_offset);
    length = extended;
  }
  if (control && length > kMaxControlPayload) {
    throw FrameError("control frame payload of " + std::to_string(length) + " bytes (limit 125)", stream_offset);
  }
  if (length > max_payload) {
    throw MessageTooLarge("websocket frame at stream byte " + std::to_string(stream_offset) + ": payload of " +
                          std::to_string(length) + " bytes over the limit of " + std::to_string(max_payload));
  }
  if (size - header < length) return 0;
  frame.fin = fin;
  frame.opcode = static_cast<Opcode>(opcode);
  frame.payload.assign(data + header, data + header + length);
  return header + static_cast<std::size_t>(length);
}

}  // namespace tavis::batch::remote
