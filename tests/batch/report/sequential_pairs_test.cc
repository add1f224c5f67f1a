// Which cells the sequential test pairs and which stop together: head with every other camera of
// its label, the base scene with each perturbation, the label pairs named, never across scenes.
#include "batch/report/sequential_pairs.h"

#include <gtest/gtest.h>

#include <deque>
#include <string>
#include <vector>

namespace tavis::batch::report {
namespace {

struct Cells {
  std::deque<cell::EvaluationCellConfig> configs;  // stable addresses
  std::vector<PairingCell> cells;

  void Add(CameraProtocol camera, const std::string& label, uint64_t seed = 0,
           std::vector<std::string> perturbations = {}, const std::string& task = "clutter-pick-cube") {
    cell::EvaluationCellConfig config;
    config.task = task;
    config.camera = camera;
    config.seed = seed;
    config.perturbations = std::move(perturbations);
    configs.push_back(config);
    cells.push_back({&configs.back(), label});
  }
};

std::vector<std::string> Describe(const std::vector<SequentialPair>& pairs) {
  std::vector<std::string> text;
  for (const SequentialPair& pair : pairs)
    text.push_back(pair.kind + " " + std::to_string(pair.first) + "-" + std::to_string(pair.second));
  return text;
}

TEST(SequentialPairs, PairsHeadWithEachOtherCameraOfTheSameLabelAndSeed) {
  Cells cells;
  cells.Add(CameraProtocol::kHead, "expert");                        // 0
  cells.Add(CameraProtocol::kFixed, "expert");                       // 1
  cells.Add(CameraProtocol::kHeadOnly, "expert");                    // 2
  cells.Add(CameraProtocol::kFixed, "expert", 1);                    // 3: another seed, no head of its own
  cells.Add(CameraProtocol::kFixed, "hold");                         // 4: another label
  cells.Add(CameraProtocol::kHead, "expert", 0, {}, "peeking-box");  // 5: another task
  SequentialSettings settings;
  settings.enabled = true;
  const std::vector<SequentialPair> pairs = SequentialPairs(cells.cells, settings);
  EXPECT_EQ(Describe(pairs), (std::vector<std::string>{"camera 0-1", "camera 0-2"}));
  const auto groups = SequentialGroups(cells.cells.size(), pairs);
  EXPECT_EQ(groups, (std::vector<std::vector<std::size_t>>{{0, 1, 2}})) << "one head cell ties its pairs together";
  settings.enabled = false;
  EXPECT_TRUE(SequentialPairs(cells.cells, settings).empty());
}

TEST(SequentialPairs, PairsTheBaseSceneWithEachPerturbationAndTheNamedLabels) {
  Cells cells;
  cells.Add(CameraProtocol::kHead, "expert");                                     // 0
  cells.Add(CameraProtocol::kHead, "expert.runtime.move", 0, {"runtime:move"});   // 1
  cells.Add(CameraProtocol::kFixed, "expert.runtime.move", 0, {"runtime:move"});  // 2
  cells.Add(CameraProtocol::kHead, "hold");                                       // 3
  cells.Add(CameraProtocol::kHead, "hold.runtime.move", 0, {"runtime:move"});     // 4
  cells.Add(CameraProtocol::kHead, "expert", 5);                                  // 5
  cells.Add(CameraProtocol::kHead, "hold", 5);                                    // 6
  SequentialSettings settings;
  settings.enabled = true;
  settings.cameras = false;
  EXPECT_EQ(Describe(SequentialPairs(cells.cells, settings)),
            (std::vector<std::string>{"perturbation 0-1", "perturbation 3-4"}));
  settings.perturbations = false;
  settings.policies = {{"expert", "hold"}};
  const std::vector<SequentialPair> pairs = SequentialPairs(cells.cells, settings);
  EXPECT_EQ(Describe(pairs), (std::vector<std::string>{"policy 0-3", "policy 1-4", "policy 5-6"}))
      << "the same camera and perturbation, each seed apart";
  EXPECT_EQ(SequentialGroups(cells.cells.size(), pairs),
            (std::vector<std::vector<std::size_t>>{{0, 3}, {1, 4}, {5, 6}}));
}

TEST(SequentialPairs, SettingsSurviveTheirJson) {
  SequentialSettings settings;
  settings.enabled = true;
  settings.test = {0.01, 4};
  settings.cameras = false;
  settings.policies = {{"a", "b"}};
  const nlohmann::ordered_json json = SequentialSettingsJson(settings);
  EXPECT_EQ(json.dump(), R"({"alpha":0.01,"block":4,"pairs":["perturbations"],"policies":[["a","b"]]})");
  const SequentialSettings back = SequentialSettingsFromJson(json);
  EXPECT_TRUE(back.enabled);
  EXPECT_EQ(back.test.alpha, 0.01);
  EXPECT_EQ(back.test.block, 4);
  EXPECT_FALSE(back.cameras);
  EXPECT_TRUE(back.perturbations);
  EXPECT_EQ(back.policies, settings.policies);
  EXPECT_FALSE(SequentialSettingsFromJson(nullptr).enabled);
  EXPECT_TRUE(SequentialSettingsJson(SequentialSettings{}).is_null()) << "off: nothing in the spec's JSON";
}

TEST(SequentialPairs, EveryPairDecidedNeedsEachOne) {
  const Outcomes wins(10, true), losses(10, false);
  const SequentialTestSettings test{0.05, 5};
  EXPECT_TRUE(EveryPairDecided({{&wins, &losses}, {&losses, &wins}}, test));
  EXPECT_FALSE(EveryPairDecided({{&wins, &losses}, {&wins, &wins}}, test));
  EXPECT_TRUE(EveryPairDecided({}, test));
}

}  // namespace
}  // namespace tavis::batch::report
