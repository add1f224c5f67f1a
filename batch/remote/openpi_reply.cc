#include "batch/remote/openpi_reply.h"

#include <stdexcept>

namespace tavis::remote {
namespace {

std::optional<double> NumberAt(const Value& reply, std::string_view group, std::string_view key) {
  const Value* section = reply.Find(group);
  const Value* entry = section != nullptr ? section->Find(key) : nullptr;
  if (entry == nullptr) return std::nullopt;
  try {
    return NumberAsDouble(*entry, key);
  } catch (const std::invalid_argument&) {
    return std::nullopt;
  }
}

}  // namespace

ActionChunk ReadActionChunk(const Value& reply) {
  const Value* actions = reply.Find("actions");
  if (actions == nullptr) throw std::invalid_argument("openpi reply has no \"actions\" entry");
  const NdArray& array = actions->as<NdArray>("openpi reply \"actions\"");
  if (array.shape.size() != 2) {
    throw std::invalid_argument("openpi reply \"actions\" has " + std::to_string(array.shape.size()) +
                                " dimensions, expected 2 (horizon x action dim)");
  }
  ActionChunk chunk;
  chunk.values = FloatArrayToDoubles(array);  // checks the size first, so the dimensions fit int
  chunk.horizon = static_cast<int>(array.shape[0]);
  chunk.dim = static_cast<int>(array.shape[1]);
  chunk.dtype = array.dtype;
  return chunk;
}

ReplyTimings ReadReplyTimings(const Value& reply) {
  return {NumberAt(reply, "server_timing", "infer_ms"), NumberAt(reply, "server_timing", "prev_total_ms"),
          NumberAt(reply, "policy_timing", "infer_ms")};
}

}  // namespace tavis::remote
