#include "batch/output/setting_error.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

namespace tavis::batch::output {

SettingError::SettingError(const std::string& key, const std::string& problem)
    : std::invalid_argument(key + " " + problem), key_(key), problem_(problem) {}

std::string SettingKey(const std::string& key) { return std::string(1, '\0') + key + std::string(1, '\0'); }

std::string NameSettings(const std::string& text, const SettingNamer& name_of) {
  std::string named;
  std::size_t from = 0;
  for (std::size_t open = text.find('\0'); open != std::string::npos; open = text.find('\0', from)) {
    const std::size_t close = text.find('\0', open + 1);
    if (close == std::string::npos) break;
    named += text.substr(from, open - from) + name_of(text.substr(open + 1, close - open - 1));
    from = close + 1;
  }
  return named + text.substr(from);
}

std::string NumberText(double value) {
  if (std::isfinite(value) && value == std::floor(value) && std::fabs(value) < 1e15) {
    return std::to_string(static_cast<int64_t>(value));
  }
  std::ostringstream text;
  text << value;
  return text.str();
}

void CheckSettingRange(const std::string& key, double value, const SettingRange& range) {
  const std::string unit = *range.unit != '\0' ? std::string(" ") + range.unit : "";
  if (!range.choices.empty()) {
    if (std::find(range.choices.begin(), range.choices.end(), value) != range.choices.end()) return;
    std::string allowed;
    for (std::size_t i = 0; i < range.choices.size(); ++i) {
      allowed += (i == 0 ? "" : i + 1 == range.choices.size() ? " or " : ", ") + NumberText(range.choices[i]);
    }
    throw SettingError(key, "must be " + allowed + unit + ", got " + NumberText(value));
  }
  if (!(value >= range.low)) {
    throw SettingError(key, "must be at least " + NumberText(range.low) + unit + ", got " + NumberText(value));
  }
  if (!(value <= range.high)) {
    throw SettingError(key, "must be at most " + NumberText(range.high) + unit + ", got " + NumberText(value));
  }
}

}  // namespace tavis::batch::output
