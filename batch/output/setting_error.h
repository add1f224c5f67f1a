// A bad setting named as the records name it: by its key in cell.json, a sweep spec or a
// dataset's spool ("episodes must be at least 1, got 0"). Library code does not know how a value
// reached it (a flag, a spec key, a Python argument), so it names the setting; a command that took
// the value from a flag names the flag instead (tools/option_parsing.h, ErrorMessage). Advice that
// names settings in passing ("resume with a larger max_attempts") is a SettingsAdvice.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace tavis::batch::output {

// How a command names a setting given by key (its flag: "max_attempts" -> "--max-attempts").
using SettingNamer = std::function<std::string(const std::string& key)>;

// An error whose message names settings, which a command may name as its user typed them.
class NamesSettings {
 public:
  virtual ~NamesSettings() = default;
  // The message with each setting named as `name_of` says (what() names them by key).
  virtual std::string MessageNaming(const SettingNamer& name_of) const = 0;
};

class SettingError : public std::invalid_argument, public NamesSettings {
 public:
  // what(): "KEY PROBLEM", e.g. "episodes" and "must be at least 1, got 0".
  SettingError(const std::string& key, const std::string& problem);
  const std::string& key() const { return key_; }
  const std::string& problem() const { return problem_; }
  std::string MessageNaming(const SettingNamer& name_of) const override { return name_of(key_) + " " + problem_; }

 private:
  std::string key_;
  std::string problem_;
};

// A setting's key marked in a SettingsAdvice's text: "give " + SettingKey("overwrite") + " to ...".
// The marks are NUL characters, which no path or value in a message holds; only a SettingsAdvice
// may carry them (another exception's what() would end at the first).
std::string SettingKey(const std::string& key);
// `text` with each marked key written as name_of(key).
std::string NameSettings(const std::string& text, const SettingNamer& name_of);

// Advice or a refusal that names settings in passing ("give overwrite to replace them or resume
// to finish an interrupted cell", the keys marked by SettingKey), as an exception of type Base:
// what() names each by its key, a command by its flag.
template <typename Base>
class SettingsAdvice : public Base, public NamesSettings {
 public:
  explicit SettingsAdvice(const std::string& text)
      : Base(NameSettings(text, [](const std::string& key) { return key; })), text_(text) {}
  std::string MessageNaming(const SettingNamer& name_of) const override { return NameSettings(text_, name_of); }

 private:
  std::string text_;
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
