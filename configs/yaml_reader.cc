#include "configs/yaml_reader.h"

#include <yaml-cpp/yaml.h>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include "configs/input_file.h"

namespace tavis::configs {
namespace {

std::string JoinPath(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

// yaml-cpp keeps the first of two equal keys and drops the second without a word, so every
// mapping of a parsed document is walked once for repeated keys (iteration still shows both).
void RejectDuplicateKeys(const YAML::Node& node, const std::string& file, const std::string& key_path) {
  if (node.IsSequence()) {
    for (size_t i = 0; i < node.size(); ++i) {
      RejectDuplicateKeys(node[i], file, key_path + "[" + std::to_string(i) + "]");
    }
    return;
  }
  if (!node.IsMap()) return;
  std::map<std::string, int> line_of_key;
  for (const auto& entry : node) {
    const std::string key = entry.first.IsScalar() ? entry.first.Scalar() : YAML::Dump(entry.first);
    const int line = entry.first.Mark().line + 1;
    const auto [first, inserted] = line_of_key.emplace(key, line);
    if (!inserted) {
      throw ConfigError(file + ": " + JoinPath(key_path, key) + ": duplicate key '" + key + "' (lines " +
                        std::to_string(first->second) + " and " + std::to_string(line) + ")");
    }
    RejectDuplicateKeys(entry.second, file, JoinPath(key_path, key));
  }
}

YAML::Node Checked(const YAML::Node& root, const std::string& file) {
  RejectDuplicateKeys(root, file, "");
  return root;
}

std::string FormatBound(double bound) {
  std::ostringstream text;
  text << bound;
  return text.str();
}

// A whole decimal literal that strtod reads but cannot represent (1e400, 1e-400).
bool IsOutOfRangeNumber(const std::string& text) {
  char* end = nullptr;
  errno = 0;
  std::strtod(text.c_str(), &end);
  return !text.empty() && end != text.c_str() && *end == '\0' && errno == ERANGE;
}

// Edits (insertions, deletions, substitutions) that turn `a` into `b`.
std::size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// " (did you mean 'robots'?); known keys: ..." for an unknown key, from the keys the reader asked
// for: a typo is shown its fix.
std::string KnownKeysHint(const std::string& key, const std::set<std::string>& known) {
  if (known.empty()) return "";
  std::string nearest;
  std::size_t distance = 3;  // more than 2 edits is another word, not a typo
  std::string names;
  for (const std::string& name : known) {
    names += (names.empty() ? "" : ", ") + name;
    const std::size_t edits = EditDistance(key, name);
    if (edits < distance && edits < name.size()) {
      distance = edits;
      nearest = name;
    }
  }
  return (nearest.empty() ? "" : " (did you mean '" + nearest + "'?)") + std::string("; known keys: ") + names;
}

}  // namespace

std::string YamlValue::ReadFileText(const std::string& path) {
  // A missing file cannot be opened; anything else that is not a file is named here.
  const std::string not_a_file = WhyNotARegularFile(path);
  if (!not_a_file.empty() && std::filesystem::exists(path)) throw ConfigError(path + ": " + not_a_file);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path + ": cannot open file");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

YamlValue YamlValue::LoadFile(const std::string& path) { return LoadString(ReadFileText(path), path); }

YamlValue YamlValue::LoadString(const std::string& text, const std::string& source_name) {
  try {
    return YamlValue(Checked(YAML::Load(text), source_name), source_name, "");
  } catch (const YAML::ParserException& e) {
    throw ConfigError(source_name + ": malformed YAML: " + e.what());
  }
}

YamlValue::YamlValue(const YAML::Node& node, std::string file, std::string key_path)
    : node_(std::make_unique<YAML::Node>(node)),
      file_(std::move(file)),
      key_path_(std::move(key_path)),
      consumed_keys_(std::make_shared<std::set<std::string>>()) {}

YamlValue::YamlValue(const YamlValue& other)
    : node_(std::make_unique<YAML::Node>(*other.node_)),
      file_(other.file_),
      key_path_(other.key_path_),
      consumed_keys_(other.consumed_keys_) {}

YamlValue& YamlValue::operator=(const YamlValue& other) {
  if (this != &other) {
    node_ = std::make_unique<YAML::Node>(*other.node_);
    file_ = other.file_;
    key_path_ = other.key_path_;
    consumed_keys_ = other.consumed_keys_;
  }
  return *this;
}

YamlValue::~YamlValue() = default;

void YamlValue::Fail(const std::string& message) const {
  throw ConfigError(file_ + ": " + (key_path_.empty() ? "(top level)" : key_path_) + ": " + message);
}

std::optional<YamlValue> YamlValue::Optional(const std::string& key) const {
  if (!node_->IsMap()) Fail("expected a mapping");
  consumed_keys_->insert(key);
  const YAML::Node child = (*node_)[key];
  if (!child.IsDefined() || child.IsNull()) return std::nullopt;
  return YamlValue(child, file_, JoinPath(key_path_, key));
}

YamlValue YamlValue::Required(const std::string& key) const {
  std::optional<YamlValue> child = Optional(key);
  if (!child) Fail("missing key '" + key + "'");
  return *child;
}

void YamlValue::ExpectNoOtherKeys() const {
  for (const auto& entry : *node_) {
    const std::string key = entry.first.as<std::string>();
    if (consumed_keys_->count(key) == 0) {
      YamlValue(entry.second, file_, JoinPath(key_path_, key))
          .Fail("unknown key '" + key + "'" + KnownKeysHint(key, *consumed_keys_));
    }
  }
}

bool YamlValue::IsSequence() const { return node_->IsSequence(); }

std::vector<YamlValue> YamlValue::Elements() const {
  if (!node_->IsSequence()) Fail("expected a sequence");
  std::vector<YamlValue> elements;
  for (size_t i = 0; i < node_->size(); ++i) {
    elements.emplace_back((*node_)[i], file_, key_path_ + "[" + std::to_string(i) + "]");
  }
  return elements;
}

double YamlValue::AsDouble() const {
  double value = 0.0;
  if (!node_->IsScalar() || !YAML::convert<double>::decode(*node_, value)) {
    // yaml-cpp also refuses a number beyond the range of a double (1e400): say so.
    if (node_->IsScalar() && IsOutOfRangeNumber(node_->Scalar())) {
      Fail("number out of range, got '" + node_->Scalar() + "'");
    }
    Fail("expected a number");
  }
  if (!std::isfinite(value)) Fail("expected a finite number, got '" + node_->Scalar() + "'");
  return value;
}

double YamlValue::AsDouble(const Range& range) const {
  const double value = AsDouble();
  const bool below = range.min_excluded ? !(value > range.min) : !(value >= range.min);
  if (below || !(value <= range.max)) {
    Fail("got " + Text() + ", expected a value in " + (range.min_excluded ? "(" : "[") + FormatBound(range.min) + ", " +
         FormatBound(range.max) + "]" + (*range.unit ? std::string(" ") + range.unit : "") +
         (*range.why ? std::string(" (") + range.why + ")" : ""));
  }
  return value;
}

std::string YamlValue::Text() const {
  YAML::Emitter out;
  out.SetMapFormat(YAML::Flow);
  out.SetSeqFormat(YAML::Flow);
  out << *node_;
  return out.c_str();
}

int YamlValue::AsInt() const {
  int value = 0;
  if (!node_->IsScalar() || !YAML::convert<int>::decode(*node_, value)) Fail("expected an integer");
  return value;
}

bool YamlValue::AsBool() const {
  bool value = false;
  if (!node_->IsScalar() || !YAML::convert<bool>::decode(*node_, value)) Fail("expected true or false");
  return value;
}

std::string YamlValue::AsString() const {
  if (!node_->IsScalar()) Fail("expected a string");
  return node_->Scalar();
}

std::vector<double> YamlValue::AsDoubles() const {
  std::vector<double> values;
  for (const YamlValue& element : Elements()) values.push_back(element.AsDouble());
  return values;
}

std::vector<std::string> YamlValue::AsStrings() const {
  std::vector<std::string> values;
  for (const YamlValue& element : Elements()) values.push_back(element.AsString());
  return values;
}

Vec3 YamlValue::AsVec3() const {
  const std::vector<double> values = AsDoubles();
  if (values.size() != 3) Fail("expected 3 numbers, got " + std::to_string(values.size()));
  return Vec3(values[0], values[1], values[2]);
}

Vec3 YamlValue::AsVec3(const Range& range) const {
  const std::vector<YamlValue> elements = Elements();
  if (elements.size() != 3) Fail("expected 3 numbers, got " + std::to_string(elements.size()));
  return Vec3(elements[0].AsDouble(range), elements[1].AsDouble(range), elements[2].AsDouble(range));
}

}  // namespace tavis::configs
