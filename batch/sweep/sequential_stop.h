// DIR/sequential.json of a cell a sweep's sequential paired test ran (docs/sweeps.md): that it ran
// in blocks, the episode count it stopped at, why (its group decided, or the cap came first), and
// the decision of each of its pairs there. Written before the cell's summary.json, so a complete
// cell that stopped short says so; a cell without it holds its spec's episode count.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>

#include <nlohmann/json.hpp>

namespace tavis::batch::sweep {

void WriteSequentialStop(const std::filesystem::path& dir, const nlohmann::ordered_json& stop);

// The episodes a complete cell in DIR holds: its sequential.json's stopped_at when that is a count
// in [0, cap], else `cap`.
int64_t SequentialEpisodes(const std::filesystem::path& dir, int64_t cap);

}  // namespace tavis::batch::sweep
