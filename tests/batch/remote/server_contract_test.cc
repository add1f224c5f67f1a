// The contract a policy server declares in its metadata frame, as the client reads it: the frame
// is a network peer's, so every field's type, size and range is checked, and a plain openpi
// server's metadata (no observation_contract) declares nothing.
#include "batch/remote/server_contract.h"

#include <gtest/gtest.h>

#include <string>
#include <utility>

namespace tavis::batch::remote {
namespace {

Value::Map Entries(std::vector<std::pair<std::string, Value>> entries) {
  Value::Map map;
  for (auto& [key, value] : entries) map.push_back({Value(key), std::move(value)});
  return map;
}

Value::Map ValidContract() {
  return Entries({{"version", Value(1)},
                  {"cameras", Value(Entries({{"head", Value("observation.images.OBS_HEAD")},
                                             {"left_wrist", Value("observation.images.OBS_WRIST_LEFT")}}))},
                  {"image_width", Value(96)},
                  {"image_height", Value(96)},
                  {"state", Value(Entries({{"key", Value("observation.state")}, {"size", Value(34)}}))},
                  {"n_obs_steps", Value(11)},
                  {"chunk_length", Value(1)},
                  {"executed_steps", Value(1)},
                  {"checkpoint_sha256", Value(std::string(64, 'a'))}});
}

Value Metadata(Value::Map contract) {
  return Value(Entries({{"policy", Value("stateful")}, {kServerContractMetadata, Value(std::move(contract))}}));
}

Value::Map With(const std::string& field, Value value) {
  Value::Map contract = ValidContract();
  for (MapEntry& entry : contract) {
    if (entry.key == Value(field)) entry.value = std::move(value);
  }
  return contract;
}

std::string Refusal(const Value& metadata) {
  try {
    ParseServerContract(metadata, "ws://peer:1");
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST(ServerContract, APlainServerDeclaresNothing) {
  EXPECT_FALSE(ParseServerContract(Value(Entries({{"policy", Value("pi0")}})), "ws://peer:1").has_value());
}

TEST(ServerContract, AValidContractGivesTheLayoutAndTheSchedule) {
  const auto contract = ParseServerContract(Metadata(ValidContract()), "ws://peer:1");
  ASSERT_TRUE(contract.has_value());
  EXPECT_EQ(contract->keys.PolicyCameras(), (std::vector<std::string>{"head", "left_wrist"}));
  EXPECT_EQ(contract->keys.image_width, 96);
  EXPECT_EQ(contract->state_size, 34);
  EXPECT_EQ(contract->n_obs_steps, 11);
  EXPECT_EQ(contract->executed_steps, 1);
  EXPECT_EQ(contract->checkpoint_sha256, std::string(64, 'a'));
  EXPECT_TRUE(ContractConflicts(*contract, contract->keys, 1, 34).empty());
  const std::vector<std::string> conflicts = ContractConflicts(*contract, ContractKeys(), 5, 31);
  ASSERT_EQ(conflicts.size(), 5u);  // two cameras it lacks, the size, the state size, the executed steps
}

TEST(ServerContract, TheTaskAndRobotTrainedForAreReadWhenDeclared) {
  const auto none = ParseServerContract(Metadata(ValidContract()), "ws://peer:1");
  ASSERT_TRUE(none.has_value());
  EXPECT_EQ(none->task, "");
  EXPECT_EQ(none->robot, "");
  EXPECT_TRUE(TrainedForConflicts(*none, "conditional-pick", "gr1t2").empty()) << "declaring none compares none";
  Value::Map declared = ValidContract();
  declared.push_back({Value("task"), Value("wait-then-act")});
  declared.push_back({Value("robot"), Value("gr1t2")});
  const auto contract = ParseServerContract(Metadata(declared), "ws://peer:1");
  ASSERT_TRUE(contract.has_value());
  EXPECT_EQ(contract->task, "wait-then-act");
  EXPECT_EQ(contract->robot, "gr1t2");
  EXPECT_TRUE(TrainedForConflicts(*contract, "wait-then-act", "gr1t2").empty());
  EXPECT_EQ(
      TrainedForConflicts(*contract, "conditional-pick", "gr1t2"),
      std::vector<std::string>{
          "policy server ws://peer:1's policy was trained for task wait-then-act; this cell is conditional-pick"});
  EXPECT_EQ(TrainedForConflicts(*contract, "wait-then-act", "reachy2"),
            std::vector<std::string>{
                "policy server ws://peer:1's policy was trained for robot gr1t2; this cell's robot is reachy2"});
  EXPECT_EQ(TrainedForConflicts(*contract, "conditional-pick", "reachy2").size(), 2u);
}

TEST(ServerContract, HostileTaskAndRobotNamesAreRefused) {
  const auto refusal = [](const char* field, Value value) {
    Value::Map contract = ValidContract();
    contract.push_back({Value(field), std::move(value)});
    return Refusal(Metadata(contract));
  };
  EXPECT_NE(refusal("task", Value(7)).find("observation_contract.task must be a str, got int"), std::string::npos);
  EXPECT_NE(refusal("robot", Value(Value::Array{})).find("observation_contract.robot must be a str"),
            std::string::npos);
  const std::string too_long = refusal("task", Value(std::string(100000, 'a')));
  EXPECT_NE(too_long.find("1 to 64 lower-case letters"), std::string::npos) << too_long;
  EXPECT_NE(too_long.find("(100000 bytes)"), std::string::npos) << too_long;
  EXPECT_LT(too_long.size(), 400u) << "a long name is shown cut";
  EXPECT_NE(refusal("task", Value(std::string(65, 'a'))).find("task must be a tavis name"), std::string::npos);
  EXPECT_EQ(refusal("task", Value(std::string(64, 'a'))), "") << "64 characters is a name";
  EXPECT_NE(refusal("task", Value("")).find("task must be a tavis name"), std::string::npos);
  const std::string control = refusal("task", Value(std::string("pick\x1b[2J\n", 9)));
  EXPECT_NE(control.find("got 'pick?[2J?'"), std::string::npos) << "control characters are not shown: " << control;
  EXPECT_NE(refusal("robot", Value("GR1T2")).find("robot must be a tavis name"), std::string::npos);
  EXPECT_NE(refusal("robot", Value("-gr1t2")).find("robot must be a tavis name"), std::string::npos);
  EXPECT_NE(refusal("robot", Value("gr1 t2")).find("robot must be a tavis name"), std::string::npos);
  Value::Map twice = ValidContract();
  twice.push_back({Value("task"), Value("conditional-pick")});
  twice.push_back({Value("task"), Value("wait-then-act")});
  EXPECT_NE(Refusal(Metadata(twice)).find("task is given twice"), std::string::npos);
}

TEST(ServerContract, HostileFieldsAreRefusedNamingTheFieldAndValue) {
  EXPECT_NE(Refusal(Metadata(With("image_width", Value("96")))).find("image_width must be an int, got str"),
            std::string::npos);
  EXPECT_NE(Refusal(Metadata(With("image_width", Value(int64_t{1} << 40)))).find("must be from 8 to 4096"),
            std::string::npos);
  EXPECT_NE(Refusal(Metadata(With("cameras", Value(Entries({{"nose", Value("x")}}))))).find("unknown camera 'nose'"),
            std::string::npos);
  EXPECT_NE(Refusal(Metadata(With("cameras", Value(Entries({{"head", Value("step")}}))))).find("request field"),
            std::string::npos);
  EXPECT_NE(Refusal(Metadata(With("cameras", Value(Entries({{"head", Value(std::string(300, 'k'))}})))))
                .find("1 to 256 characters"),
            std::string::npos);
  EXPECT_NE(Refusal(Metadata(With("executed_steps", Value(2)))).find("executed_steps"), std::string::npos);
  EXPECT_NE(Refusal(Metadata(With("checkpoint_sha256", Value("ABC")))).find("64 lower-case hex"), std::string::npos);
  EXPECT_NE(Refusal(Metadata(With("state", Value(7)))).find("state must be a map"), std::string::npos);
  Value::Map extra = ValidContract();
  extra.push_back({Value("colour"), Value("red")});
  EXPECT_NE(Refusal(Metadata(extra)).find("unknown field 'colour'"), std::string::npos);
  EXPECT_NE(Refusal(Value(Entries({{kServerContractMetadata, Value(Value::Array{})}}))).find("must be a map"),
            std::string::npos);
  EXPECT_EQ(Refusal(Metadata(ValidContract())), "");
}

}  // namespace
}  // namespace tavis::batch::remote
