// A finished sweep's results in DIR, from its cells' records: summary.json, tables/<name>.md,
// .csv and .tex, and report.html, each written to a temporary name and renamed.
#pragma once

#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/sweep/sweep_spec.h"

namespace tavis::batch::sweep {

// `cell_jsons[i]` is what cells[i] records in its cell.json (cell::CellSettingsJson). Throws
// std::runtime_error naming the cell when one is not complete in DIR/cells/<id>.
void WriteSweepResults(const std::filesystem::path& dir, const nlohmann::ordered_json& spec_json,
                       const std::vector<SweepCell>& cells, const std::vector<nlohmann::json>& cell_jsons,
                       const nlohmann::ordered_json& manifest);

}  // namespace tavis::batch::sweep
