// A submission: a results folder and a JSON card saying what made it, in the spirit of RoboCasa's
// leaderboard schema (docs/verifying.md). SUBMISSION/submission.json is the card; its "results"
// names the folder of cells inside SUBMISSION (a sweep's folder, or eval cells at any depth), which
// `tavis verify SUBMISSION` re-simulates after checking the card. The card is a stranger's file:
// every field is checked for its type and form, and an error names the field.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tavis::batch::cell {

inline constexpr const char* kSubmissionCardFile = "submission.json";
inline constexpr const char* kSubmissionFormat = "tavis-submission/1";

// A card that is not valid: the message names the file and the field ("submission.json:
// training.steps: must be an integer >= 0, got \"many\"").
class SubmissionCardError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

struct SubmissionCard {
  std::string model;                // model.name
  std::string version;              // model.version
  std::string policy_family;        // model.policy_family
  std::filesystem::path results;    // the results folder, inside the submission
  std::vector<std::string> splits;  // the splits evaluated
  std::string checkpoint_sha256;    // checkpoint.sha256 as "sha256:<hex>", empty when not given
  nlohmann::json json;              // the card as read
};

// True when DIR holds a card.
bool IsSubmission(const std::filesystem::path& dir);

// Checks the card's fields (docs/verifying.md lists them) and returns them; `dir` is the
// submission. Throws SubmissionCardError naming the first bad field: a missing or mistyped one,
// an unknown format or split, a commit or hash that is not hex, a link that is not http(s), a
// results folder outside the submission (absolute, or with ".."), or one that is not a folder.
SubmissionCard ReadSubmissionCard(const std::filesystem::path& dir);

// Why a cell of the submission does not match its card, or "": its split (cell.json) is not among
// the card's splits, or its servers declared a checkpoint hash (summary.json's provenance) other
// than the card's checkpoint.sha256.
std::string CardMismatch(const SubmissionCard& card, const std::filesystem::path& cell);

// The card checked from its JSON text (`source` names it in errors); `dir` as above.
SubmissionCard ParseSubmissionCard(const std::string& text, const std::string& source,
                                   const std::filesystem::path& dir);

}  // namespace tavis::batch::cell
