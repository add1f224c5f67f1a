// `tavis sweep merge`: the outputs of the N shards of one sweep combined into one output folder
// with the results of the whole sweep, as if it had run in one piece.
#pragma once

#include <string>
#include <vector>

namespace tavis::batch::sweep {

// Refuses (std::invalid_argument naming the folders and what differs) shards of different specs,
// program versions or shard counts, a shard given twice or missing, and incomplete cells.
// OUT must not hold another sweep; its cells are copied from the shards.
void MergeSweeps(const std::vector<std::string>& shard_dirs, const std::string& out_dir, const std::string& config_dir);

}  // namespace tavis::batch::sweep
