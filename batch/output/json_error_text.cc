#include "batch/output/json_error_text.h"

namespace tavis::batch::output {

std::string JsonErrorText(const std::string& message) {
  const std::string prefix = "[json.exception.";
  if (message.rfind(prefix, 0) != 0) return message;
  const std::size_t end = message.find("] ");
  return end == std::string::npos ? message : message.substr(end + 2);
}

}  // namespace tavis::batch::output
