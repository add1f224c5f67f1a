// What an openpi reply map carries: the action chunk "actions" (horizon x dim, float32 or
// float64) and the timings the server reports (policy-interfaces.md §A1, Reply).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "batch/remote/msgpack_value.h"

namespace tavis::batch::remote {

struct ActionChunk {
  int horizon = 0;
  int dim = 0;
  std::string dtype;           // "<f4" or "<f8", as received
  std::vector<double> values;  // (horizon x dim), row-major, float32 widened exactly

  double at(int step, int column) const { return values[static_cast<std::size_t>(step) * dim + column]; }
};

// reply["actions"] as a chunk. Throws std::invalid_argument naming the fault: no "actions" key,
// not an ndarray, not 2-D, or a dtype other than "<f4"/"<f8". Values are not checked (NaN passes).
ActionChunk ReadActionChunk(const Value& reply);

// reply["actions"] of a batched request for `envs` envs: an envs x H x dim array, one chunk per
// env in the request's order. Throws std::invalid_argument naming the fault as ReadActionChunk
// does, and when the leading axis is not `envs` long.
std::vector<ActionChunk> ReadBatchedActionChunks(const Value& reply, int envs);

struct ReplyTimings {
  std::optional<double> server_infer_ms;       // server_timing.infer_ms
  std::optional<double> server_prev_total_ms;  // server_timing.prev_total_ms, from the 2nd request on
  std::optional<double> policy_infer_ms;       // policy_timing.infer_ms
};

// The timings present in the reply; absent or non-numeric entries stay empty.
ReplyTimings ReadReplyTimings(const Value& reply);

}  // namespace tavis::batch::remote
