// Strict reading of YAML files into typed structs. Every accessor names the file and the key
// path in its error; a mapping read through Required()/Optional() must have every key consumed
// (ExpectNoOtherKeys()), so a typo
// or an unknown key is an error rather than a silently ignored setting. A key given twice in one
// mapping is an error naming both lines (yaml-cpp itself keeps the first silently). A UTF-8 byte
// order mark at the start of a file is accepted (yaml-cpp skips it).
#pragma once

#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "kinematics/pose.h"

namespace YAML {
class Node;
}

namespace tavis::configs {

// Thrown for any configuration problem; what() reads "file: key.path: message".
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The interval a number must lie in, for range-checked reads. Messages print it as
// "[min, max] unit" ("(min, max]" when min is excluded) followed by `why`, if any.
struct Range {
  double min = 0.0;
  double max = 0.0;
  bool min_excluded = false;
  const char* unit = "";
  const char* why = "";
};

class YamlValue {
 public:
  // Parses `path`; throws ConfigError for a missing file or malformed YAML.
  static YamlValue LoadFile(const std::string& path);
  static YamlValue LoadString(const std::string& text, const std::string& source_name);
  // The text LoadFile parses, for a caller that also keeps it (a cell records its robot file):
  // read once, then LoadString(text, path). Throws ConfigError as LoadFile does for a path that
  // is not a readable file.
  static std::string ReadFileText(const std::string& path);

  YamlValue(const YAML::Node& node, std::string file, std::string key_path);
  YamlValue(const YamlValue& other);
  YamlValue& operator=(const YamlValue& other);
  ~YamlValue();

  // Mapping access. Each key read is recorded; ExpectNoOtherKeys() reports the rest.
  YamlValue Required(const std::string& key) const;
  std::optional<YamlValue> Optional(const std::string& key) const;
  void ExpectNoOtherKeys() const;

  std::vector<YamlValue> Elements() const;  // sequence
  bool IsSequence() const;
  double AsDouble() const;
  // A number in `range`; the error names the value as written in the file.
  double AsDouble(const Range& range) const;
  int AsInt() const;
  bool AsBool() const;
  std::string AsString() const;
  Vec3 AsVec3() const;
  Vec3 AsVec3(const Range& range) const;  // each component in `range`
  std::vector<double> AsDoubles() const;
  std::vector<std::string> AsStrings() const;

  // Shorthands for Required(key).AsX().
  double Double(const std::string& key) const { return Required(key).AsDouble(); }
  int Int(const std::string& key) const { return Required(key).AsInt(); }
  std::string String(const std::string& key) const { return Required(key).AsString(); }
  Vec3 Vector3(const std::string& key) const { return Required(key).AsVec3(); }
  double Double(const std::string& key, const Range& range) const { return Required(key).AsDouble(range); }
  Vec3 Vector3(const std::string& key, const Range& range) const { return Required(key).AsVec3(range); }

  [[noreturn]] void Fail(const std::string& message) const;
  // The node as written, flow style on one line, for messages ("[0, 0, 0]", "1e308").
  std::string Text() const;
  const std::string& key_path() const { return key_path_; }
  const std::string& file() const { return file_; }

 private:
  std::unique_ptr<YAML::Node> node_;
  std::string file_;
  std::string key_path_;
  std::shared_ptr<std::set<std::string>> consumed_keys_;
};

}  // namespace tavis::configs
