// Option values shared by the subcommands, parsed and listed the same way everywhere.
#pragma once

#include <string>
#include <utility>

namespace tavis::tools {

// "224x224" -> (224, 224); throws std::invalid_argument naming the value.
std::pair<int, int> ParseImageSize(const std::string& text);

}  // namespace tavis::tools
