// A submission's card: a valid one is read, and every malformed field is refused naming it.
#include "batch/cell/submission_card.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/thrown_message.h"

namespace tavis::batch::cell {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json GoodCard() {
  return json::parse(R"({
    "format": "tavis-submission/1",
    "model": {"name": "wta-resnet18", "version": "2026-12-02", "policy_family": "act"},
    "code": {"url": "https://github.com/example/policies", "commit": "4a952ce"},
    "checkpoint": {"url": "https://huggingface.co/example/wta",
                   "sha256": "0F343B0931126A20F133D67C2B018A3B0F343B0931126A20F133D67C2B018A3B"},
    "training": {"steps": 8000, "data": ["tavis demos conditional-pick, 200 episodes"]},
    "splits": ["id", "ood_spatial"],
    "results": "results",
    "submitter": "not checked"
  })");
}

class SubmissionCardTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("tavis_submission_card_test_" + std::to_string(getpid()));
    fs::create_directories(dir_ / "results");
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string ErrorOf(const json& card) const {
    return testing::ThrownMessage<SubmissionCardError>(
        [&] { ParseSubmissionCard(card.dump(), "submission.json", dir_); }, "no error");
  }

  fs::path dir_;
};

TEST_F(SubmissionCardTest, AValidCardIsRead) {
  std::ofstream(dir_ / kSubmissionCardFile) << GoodCard().dump(2);
  ASSERT_TRUE(IsSubmission(dir_));
  EXPECT_FALSE(IsSubmission(dir_ / "results"));
  const SubmissionCard card = ReadSubmissionCard(dir_);
  EXPECT_EQ(card.model, "wta-resnet18");
  EXPECT_EQ(card.version, "2026-12-02");
  EXPECT_EQ(card.policy_family, "act");
  EXPECT_EQ(card.results, dir_ / "results");
  EXPECT_EQ(card.splits, (std::vector<std::string>{"id", "ood-spatial"}));
  EXPECT_EQ(card.checkpoint_sha256, "sha256:0f343b0931126a20f133d67c2b018a3b0f343b0931126a20f133d67c2b018a3b");
  EXPECT_EQ(card.json["submitter"], "not checked");
  json no_hash = GoodCard();
  no_hash["checkpoint"].erase("sha256");
  EXPECT_EQ(ParseSubmissionCard(no_hash.dump(), "submission.json", dir_).checkpoint_sha256, "");
}

TEST_F(SubmissionCardTest, EachBadFieldIsNamed) {
  const auto with = [](const json::json_pointer& where, const json& value) {
    json card = GoodCard();
    if (value.is_discarded()) {
      card[where.parent_pointer()].erase(where.back());
    } else {
      card[where] = value;
    }
    return card;
  };
  const json gone = json(json::value_t::discarded);
  const std::vector<std::pair<json, std::string>> cases = {
      {with("/format"_json_pointer, "tavis-submission/0"),
       "format: must be \"tavis-submission/1\", got \"tavis-submission/0\""},
      {with("/model/name"_json_pointer, gone), "model.name: missing (a non-empty string)"},
      {with("/model/version"_json_pointer, 3), "model.version: must be a non-empty string, got 3"},
      {with("/model/policy_family"_json_pointer, ""), "model.policy_family: must be a non-empty string, got \"\""},
      {with("/model/name"_json_pointer, "a\nb"), "model.name: holds a control character"},
      {with("/code/url"_json_pointer, "file:///etc/passwd"),
       "code.url: must be an http(s) link, got \"file:///etc/passwd\""},
      {with("/code/commit"_json_pointer, "main"), "code.commit: must be 7 to 40 hex digits, got \"main\""},
      {with("/checkpoint/url"_json_pointer, gone), "checkpoint.url: missing (a non-empty string)"},
      {with("/checkpoint/sha256"_json_pointer, "abc"), "checkpoint.sha256: must be 64 hex digits, got \"abc\""},
      {with("/training/steps"_json_pointer, "many"), "training.steps: must be an integer >= 0, got \"many\""},
      {with("/training/steps"_json_pointer, -1), "training.steps: must be an integer >= 0, got -1"},
      {with("/training/data"_json_pointer, json::array()),
       "training.data: must be a non-empty list of strings, got []"},
      {with("/training/data"_json_pointer, json::array({"ok", 5})),
       "training.data.1: must be a non-empty string, got 5"},
      {with("/splits"_json_pointer, json::array({"id", "ood-everything"})),
       "splits.1: unknown split \"ood-everything\" (id, ood-spatial, ood-init-pose)"},
      {with("/results"_json_pointer, "../elsewhere"),
       "results: must be a folder inside the submission (relative, no \"..\"), got \"../elsewhere\""},
      {with("/results"_json_pointer, "/etc"),
       "results: must be a folder inside the submission (relative, no \"..\"), got \"/etc\""},
      {with("/model"_json_pointer, "x"), "model.name: missing (a non-empty string)"},
  };
  for (const auto& [card, error] : cases) EXPECT_EQ(ErrorOf(card), "submission.json: " + error);
  EXPECT_EQ(ErrorOf(with("/results"_json_pointer, "missing")),
            "submission.json: results: " + (dir_ / "missing").string() + " is not a folder");
  EXPECT_EQ(testing::ThrownMessage<SubmissionCardError>([&] { ParseSubmissionCard("[1, 2]", "submission.json", dir_); },
                                                        "no error"),
            "submission.json: must be a JSON object, got [1,2]");
  EXPECT_EQ(testing::ThrownMessage<SubmissionCardError>(
                [&] { ParseSubmissionCard("{\"format\": ", "submission.json", dir_); }, "no error")
                .rfind("submission.json: not valid JSON: ", 0),
            0u);
}

TEST_F(SubmissionCardTest, AHugeOrMissingCardIsRefused) {
  EXPECT_NE(
      testing::ThrownMessage<SubmissionCardError>([&] { ReadSubmissionCard(dir_); }, "no error").find("cannot be read"),
      std::string::npos);
  std::ofstream(dir_ / kSubmissionCardFile) << std::string(2 << 20, ' ');
  EXPECT_NE(testing::ThrownMessage<SubmissionCardError>([&] { ReadSubmissionCard(dir_); }, "no error")
                .find("bytes: not a card"),
            std::string::npos);
}

// A cell of the submission must be of a split the card lists, and a served cell's declared
// checkpoint must be the card's.
TEST_F(SubmissionCardTest, ACellOfAnotherSplitOrCheckpointDoesNotMatch) {
  std::ofstream(dir_ / kSubmissionCardFile) << GoodCard().dump(2);
  const SubmissionCard card = ReadSubmissionCard(dir_);
  const fs::path cell = dir_ / "results" / "cell";
  fs::create_directories(cell);
  std::ofstream(cell / "cell.json") << R"({"split": "id"})";
  EXPECT_EQ(CardMismatch(card, cell), "");
  std::ofstream(cell / "summary.json") << R"({"provenance": {"policy": {"checkpoint_sha256": [null, "sha256:)"
                                       << std::string(64, '1') << R"("]}}})";
  EXPECT_EQ(CardMismatch(card, cell), "its server declared checkpoint sha256:" + std::string(64, '1') +
                                          ", the card's checkpoint.sha256 is " + card.checkpoint_sha256);
  std::ofstream(cell / "summary.json") << R"({"provenance": {"policy": {"checkpoint_sha256": [")"
                                       << card.checkpoint_sha256 << R"("]}}})";
  EXPECT_EQ(CardMismatch(card, cell), "");
  std::ofstream(cell / "cell.json") << R"({"split": "ood-init-pose"})";
  EXPECT_EQ(CardMismatch(card, cell), "split ood-init-pose is not among the card's splits");
}

}  // namespace
}  // namespace tavis::batch::cell
