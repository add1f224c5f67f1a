#include "batch/remote/openpi_reply.h"

#include <stdexcept>

namespace tavis::batch::remote {
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

const NdArray& ActionsArray(const Value& reply, std::size_t dimensions, const char* expected) {
  const Value* actions = reply.Find("actions");
  if (actions == nullptr) throw std::invalid_argument("openpi reply has no \"actions\" entry");
  const NdArray& array = actions->as<NdArray>("openpi reply \"actions\"");
  if (array.shape.size() != dimensions) {
    throw std::invalid_argument("openpi reply \"actions\" has " + std::to_string(array.shape.size()) +
                                " dimensions, expected " + std::to_string(dimensions) + " (" + expected + ")");
  }
  return array;
}

}  // namespace

ActionChunk ReadActionChunk(const Value& reply) {
  const NdArray& array = ActionsArray(reply, 2, "horizon x action dim");
  ActionChunk chunk;
  chunk.values = FloatArrayToDoubles(array);  // checks the size first, so the dimensions fit int
  chunk.horizon = static_cast<int>(array.shape[0]);
  chunk.dim = static_cast<int>(array.shape[1]);
  chunk.dtype = array.dtype;
  return chunk;
}

std::vector<ActionChunk> ReadBatchedActionChunks(const Value& reply, int envs) {
  const NdArray& array = ActionsArray(reply, 3, "envs x horizon x action dim, for a batched request");
  const std::vector<double> values = FloatArrayToDoubles(array);  // checks the size first
  if (array.shape[0] != envs) {
    throw std::invalid_argument("openpi reply \"actions\" answers " + std::to_string(array.shape[0]) +
                                " envs, but the batched request asked for " + std::to_string(envs));
  }
  std::vector<ActionChunk> chunks(static_cast<std::size_t>(envs));
  const std::size_t per_env = static_cast<std::size_t>(array.shape[1] * array.shape[2]);
  for (std::size_t i = 0; i < chunks.size(); ++i) {
    chunks[i].horizon = static_cast<int>(array.shape[1]);
    chunks[i].dim = static_cast<int>(array.shape[2]);
    chunks[i].dtype = array.dtype;
    chunks[i].values.assign(values.begin() + static_cast<std::ptrdiff_t>(i * per_env),
                            values.begin() + static_cast<std::ptrdiff_t>((i + 1) * per_env));
  }
  return chunks;
}

ReplyTimings ReadReplyTimings(const Value& reply) {
  return {NumberAt(reply, "server_timing", "infer_ms"), NumberAt(reply, "server_timing", "prev_total_ms"),
          NumberAt(reply, "policy_timing", "infer_ms")};
}

}  // namespace tavis::batch::remote
