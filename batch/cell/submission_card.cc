#include "batch/cell/submission_card.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iterator>

#include "batch/output/json_error_text.h"
#include "scenarios/split.h"

namespace tavis::batch::cell {
namespace {

using nlohmann::json;

// What a field's value is shown as in an error: its JSON, cut short.
std::string Shown(const json& value) {
  const std::string text = value.dump();
  return text.size() > 80 ? text.substr(0, 77) + "..." : text;
}

class CardReader {
 public:
  CardReader(const json& card, std::string source) : card_(card), source_(std::move(source)) {}

  [[noreturn]] void Fail(const std::string& field, const std::string& what) const {
    throw SubmissionCardError(source_ + ": " + field + ": " + what);
  }

  // The value at a dotted path ("model.name"); null when absent.
  const json* At(const std::string& field) const {
    const json* value = &card_;
    std::size_t begin = 0;
    while (begin <= field.size()) {
      const std::size_t dot = std::min(field.find('.', begin), field.size());
      const std::string key = field.substr(begin, dot - begin);
      if (value->is_array()) {  // a list's item by its index ("training.data.1")
        const std::size_t index = key.find_first_not_of("0123456789") == std::string::npos ? std::stoul(key) : ~0ul;
        if (index >= value->size()) return nullptr;
        value = &(*value)[index];
      } else {
        if (!value->is_object() || !value->contains(key)) return nullptr;
        value = &(*value)[key];
      }
      begin = dot + 1;
    }
    return value;
  }

  std::string Text(const std::string& field, bool required = true, std::size_t max_size = 200) const {
    const json* value = At(field);
    if (value == nullptr) {
      if (required) Fail(field, "missing (a non-empty string)");
      return "";
    }
    if (!value->is_string() || value->get<std::string>().empty())
      Fail(field, "must be a non-empty string, got " + Shown(*value));
    const std::string text = value->get<std::string>();
    if (text.size() > max_size) Fail(field, "longer than " + std::to_string(max_size) + " characters");
    if (std::any_of(text.begin(), text.end(), [](unsigned char c) { return c < 0x20; }))
      Fail(field, "holds a control character");
    return text;
  }

  std::string Link(const std::string& field, bool required) const {
    const std::string link = Text(field, required, 2000);
    if (!link.empty() && link.rfind("https://", 0) != 0 && link.rfind("http://", 0) != 0)
      Fail(field, "must be an http(s) link, got " + Shown(link));
    return link;
  }

  std::string Hex(const std::string& field, bool required, std::size_t min_digits, std::size_t max_digits) const {
    std::string hex = Text(field, required, 80);
    if (hex.rfind("sha256:", 0) == 0 && max_digits == 64) hex = hex.substr(7);
    const bool is_hex = std::all_of(hex.begin(), hex.end(), [](unsigned char c) { return std::isxdigit(c) != 0; });
    if (!hex.empty() && (!is_hex || hex.size() < min_digits || hex.size() > max_digits)) {
      Fail(field, "must be " +
                      (min_digits == max_digits ? std::to_string(max_digits)
                                                : std::to_string(min_digits) + " to " + std::to_string(max_digits)) +
                      " hex digits, got " + Shown(*At(field)));
    }
    std::transform(hex.begin(), hex.end(), hex.begin(), [](unsigned char c) { return std::tolower(c); });
    return hex;
  }

  int64_t Count(const std::string& field) const {
    const json* value = At(field);
    if (value == nullptr) Fail(field, "missing (an integer >= 0)");
    if (!value->is_number_integer() || value->get<int64_t>() < 0)
      Fail(field, "must be an integer >= 0, got " + Shown(*value));
    return value->get<int64_t>();
  }

  std::vector<std::string> TextList(const std::string& field) const {
    const json* value = At(field);
    if (value == nullptr) Fail(field, "missing (a non-empty list of strings)");
    if (!value->is_array() || value->empty()) Fail(field, "must be a non-empty list of strings, got " + Shown(*value));
    std::vector<std::string> items;
    for (std::size_t i = 0; i < value->size(); ++i) items.push_back(Text(field + "." + std::to_string(i)));
    return items;
  }

 private:
  const json& card_;
  std::string source_;
};

// A card is a page of JSON; anything far larger is not one (and is not read whole).
constexpr std::uintmax_t kMaxCardBytes = 1 << 20;

json ReadJsonOrNull(const std::filesystem::path& path) {
  std::ifstream in(path);
  return in ? json::parse(in, nullptr, false) : json();
}

}  // namespace

std::string CardMismatch(const SubmissionCard& card, const std::filesystem::path& cell) {
  const json settings = ReadJsonOrNull(cell / "cell.json");
  const std::string split =
      settings.is_object() && settings.value("split", json()).is_string() ? settings["split"].get<std::string>() : "";
  if (!split.empty() && std::find(card.splits.begin(), card.splits.end(), split) == card.splits.end())
    return "split " + split + " is not among the card's splits";
  if (card.checkpoint_sha256.empty()) return "";
  const json summary = ReadJsonOrNull(cell / "summary.json");
  if (!summary.is_object()) return "";
  const json declared = summary.value("provenance", json::object())
                            .value("policy", json::object())
                            .value("checkpoint_sha256", json::array());
  if (!declared.is_array()) return "";
  for (const json& hash : declared) {
    if (hash.is_string() && hash.get<std::string>() != card.checkpoint_sha256)
      return "its server declared checkpoint " + hash.get<std::string>() + ", the card's checkpoint.sha256 is " +
             card.checkpoint_sha256;
  }
  return "";
}

bool IsSubmission(const std::filesystem::path& dir) {
  return std::filesystem::is_regular_file(dir / kSubmissionCardFile);
}

SubmissionCard ParseSubmissionCard(const std::string& text, const std::string& source,
                                   const std::filesystem::path& dir) {
  json card;
  try {
    card = json::parse(text);
  } catch (const json::exception& error) {
    throw SubmissionCardError(source + ": not valid JSON: " + output::JsonErrorText(error.what()));
  }
  if (!card.is_object()) throw SubmissionCardError(source + ": must be a JSON object, got " + Shown(card));
  const CardReader read(card, source);
  SubmissionCard result;
  result.json = card;
  if (read.Text("format") != kSubmissionFormat)
    read.Fail("format", std::string("must be \"") + kSubmissionFormat + "\", got " + Shown(card["format"]));
  result.model = read.Text("model.name");
  result.version = read.Text("model.version");
  result.policy_family = read.Text("model.policy_family");
  read.Link("code.url", true);
  read.Hex("code.commit", true, 7, 40);
  read.Link("checkpoint.url", true);
  const std::string checkpoint = read.Hex("checkpoint.sha256", false, 64, 64);
  if (!checkpoint.empty()) result.checkpoint_sha256 = "sha256:" + checkpoint;
  read.Count("training.steps");
  read.TextList("training.data");
  result.splits = read.TextList("splits");
  for (std::size_t i = 0; i < result.splits.size(); ++i) {
    scenarios::Split split = scenarios::Split::kId;
    try {
      split = scenarios::ParseSplit(result.splits[i]);
    } catch (const std::exception&) {
      read.Fail("splits." + std::to_string(i),
                "unknown split " + Shown(result.splits[i]) + " (id, ood-spatial, ood-init-pose)");
    }
    result.splits[i] = scenarios::ToString(split);
  }
  const std::string results = read.Text("results", true, 1000);
  const std::filesystem::path relative(results);
  if (relative.is_absolute() ||
      std::any_of(relative.begin(), relative.end(), [](const std::filesystem::path& part) { return part == ".."; }))
    read.Fail("results", "must be a folder inside the submission (relative, no \"..\"), got " + Shown(results));
  result.results = dir / relative;
  if (!std::filesystem::is_directory(result.results))
    read.Fail("results", result.results.string() + " is not a folder");
  return result;
}

SubmissionCard ReadSubmissionCard(const std::filesystem::path& dir) {
  const std::filesystem::path path = dir / kSubmissionCardFile;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SubmissionCardError(path.string() + ": cannot be read");
  std::error_code error;
  if (std::filesystem::file_size(path, error) > kMaxCardBytes)
    throw SubmissionCardError(path.string() + ": over " + std::to_string(kMaxCardBytes) + " bytes: not a card");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return ParseSubmissionCard(text, path.string(), dir);
}

}  // namespace tavis::batch::cell
