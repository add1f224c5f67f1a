// The sweep's report as one self-contained HTML file (inline CSS and SVG, no script, nothing
// fetched): per policy label the success rates with their intervals per task, split and protocol;
// the paper's Figures 3 and 4 and headline numbers; GALT distributions per label and robot with
// the human references marked; successful-episode length distributions; every table; the cells
// with their labels and numbers; the spec and the manifest. Written from summary.json, so its numbers
// are the JSON's; each cell's numbers carry data-cell / data-field attributes for checkers.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace tavis::batch::report {

std::string SweepHtmlReport(const nlohmann::ordered_json& summary, const nlohmann::ordered_json& manifest);

}  // namespace tavis::batch::report
