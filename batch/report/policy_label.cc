#include "batch/report/policy_label.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace tavis::batch::report {

std::string PolicyLabelOf(const CellCounts& cell) {
  const std::filesystem::path policy_file = std::filesystem::path(cell.source).parent_path() / "policy.json";
  std::ifstream in(policy_file);
  if (in) {
    const nlohmann::json policy = nlohmann::json::parse(in, nullptr, false);
    if (policy.is_object() && policy.contains("label") && policy["label"].is_string()) return policy["label"];
    throw std::runtime_error(policy_file.string() + ": needs a string \"label\"");
  }
  return cell.policy.empty() ? "unlabelled" : cell.policy;
}

}  // namespace tavis::batch::report
