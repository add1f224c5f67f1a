// A bad setting named as the records name it: by its key in cell.json, a sweep spec or a
// dataset's spool ("episodes must be at least 1, got 0"). Library code does not know how a value
// reached it (a flag, a spec key, a Python argument), so it names the setting; a command that took
// the value from a flag names the flag instead (tools/option_parsing.h, SettingErrorWithFlag).
#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace tavis::batch::output {

class SettingError : public std::invalid_argument {
 public:
  // what(): "KEY PROBLEM", e.g. "episodes" and "must be at least 1, got 0".
  SettingError(const std::string& key, const std::string& problem);
  const std::string& key() const { return key_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string key_;
  std::string problem_;
};

// The values a number setting takes: [low, high] (`unit` for messages: "s", "MiB"), or one of
// `choices` when there are any.
struct SettingRange {
  double low = 0.0;
  double high = 0.0;
  const char* unit = "";
  std::vector<double> choices;

  static SettingRange Between(double low, double high, const char* unit = "") { return {low, high, unit, {}}; }
  static SettingRange OneOf(std::vector<double> values) { return {0.0, 0.0, "", std::move(values)}; }
};

// A number as messages print it: an integer without a decimal point, else as `<<` writes it.
std::string NumberText(double value);

// Throws SettingError naming `key` unless `value` is allowed: "must be at least 1, got 0",
// "must be at most 4096, got 5000", "must be 60 or 20, got 30".
void CheckSettingRange(const std::string& key, double value, const SettingRange& range);

}  // namespace tavis::batch::output
