// nlohmann::json's messages start with its exception id ("[json.exception.type_error.302] type
// must be number, but is string"): errors about a damaged file show only what is wrong.
#pragma once

#include <string>

namespace tavis::batch::output {

// `message` without a leading "[json.exception.NAME] " (unchanged when it has none).
std::string JsonErrorText(const std::string& message);

}  // namespace tavis::batch::output
