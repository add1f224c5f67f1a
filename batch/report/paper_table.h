// Table 1 of the paper as LaTeX: one policy label's success rates with both suites, a column per
// robot x split x camera (GR1T2 then Reachy2; id, ood-spatial, ood-init-pose; head, fixed: those
// present), a row per task, each suite followed by its mean (the task average, as the paper's
// text). Written from summary.json's "success" section.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace tavis::batch::report {

// Needs \usepackage{booktabs}; rates in percent with one decimal, "--" where not evaluated.
std::string PaperTable1Latex(const nlohmann::ordered_json& summary, const std::string& label);

}  // namespace tavis::batch::report
