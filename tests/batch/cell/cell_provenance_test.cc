// summary.json's provenance: the config files a cell read by their sha256 (as sha256sum prints
// it), the policy's identity with a server's metadata frame bounded and its checkpoint hash taken
// only when it is one, the machine and the time split.
#include "batch/cell/cell_provenance.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <utility>

#include "batch/cell/episode_times.h"
#include "batch/output/program_version.h"
#include "tests/batch/cell/example_cells.h"

namespace tavis::batch::cell {
namespace {

using remote::Value;

Value Frame(Value::Map entries) { return Value(std::move(entries)); }

std::string Sha256sum(const std::string& path) {
  FILE* pipe = popen(("sha256sum '" + path + "'").c_str(), "r");
  char digest[65] = {};
  const std::size_t read = pipe != nullptr ? std::fread(digest, 1, 64, pipe) : 0;
  if (pipe != nullptr) pclose(pipe);
  return read == 64 ? std::string("sha256:") + digest : "";
}

TEST(CellProvenance, NamesEveryConfigFileTheCellReadBySha256) {
  EvaluationCellConfig config = ServedCellWithOptions();
  config.config_dir = TAVIS_CONFIG_DIR;
  config.observation_keys = "libero";
  config.perturbations = {"lighting:dim", "camera:fov-wide"};
  CellResult result;
  result.config = config;
  const nlohmann::json provenance = CellProvenanceJson(result, {"ckpt-a", 3});
  const nlohmann::json& files = provenance.at("config_files");
  ASSERT_EQ(files.size(), 4u) << files.dump(2);
  EXPECT_EQ(files["robot"]["file"], "gr1t2.yaml");
  EXPECT_EQ(files["robot"]["sha256"], Sha256sum(std::string(TAVIS_CONFIG_DIR) + "/robots/gr1t2.yaml"));
  EXPECT_EQ(files["observation_keys"]["sha256"], Sha256sum(std::string(TAVIS_CONFIG_DIR) + "/policy_keys/libero.yaml"));
  EXPECT_EQ(files["perturbations/lighting"]["sha256"],
            Sha256sum(std::string(TAVIS_CONFIG_DIR) + "/perturbations/lighting.yaml"));
  EXPECT_EQ(files["perturbations/camera"]["file"], "camera.yaml");
  // No folder of this machine in the record.
  EXPECT_EQ(provenance.dump().find(TAVIS_CONFIG_DIR), std::string::npos);
  EXPECT_EQ(provenance["program"]["version"], output::ProgramVersion());
  EXPECT_EQ(provenance["program"]["git_revision"], output::ProgramRevision());
  EXPECT_EQ(provenance["policy"]["label"], "ckpt-a");
  EXPECT_EQ(provenance["policy"]["name"], "openpi");
  EXPECT_EQ(provenance["policy"]["servers"], nlohmann::json(config.servers));
  EXPECT_EQ(provenance["machine"]["threads_used"], 3);
  EXPECT_TRUE(provenance["machine"]["cpu_model"].is_string());
}

TEST(CellProvenance, ABuiltInPolicyHasItsNameAsLabelAndNoServers) {
  EvaluationCellConfig config = HoldCellOnReachy();
  config.config_dir = TAVIS_CONFIG_DIR;
  CellResult result;
  result.config = config;
  result.wall_s = 2.5;
  const nlohmann::json provenance = CellProvenanceJson(result, {"", 1});
  EXPECT_EQ(provenance["policy"], nlohmann::json({{"label", "hold"}, {"name", "hold"}}));
  EXPECT_EQ(provenance["config_files"].size(), 1u);
  EXPECT_EQ(provenance["time"], nlohmann::json({{"wall_s", 2.5}, {"episodes", EpisodeTimesSummaryJson({})}}))
      << "no episode of this result was timed";
}

// A robot file gone by the time the summary is written is recorded as such: the cell that ran
// is not lost over its provenance.
TEST(CellProvenance, AnUnreadableConfigFileIsRecordedNotThrown) {
  EvaluationCellConfig config = HoldCellOnReachy();
  config.config_dir = "/nonexistent";
  CellResult result;
  result.config = config;
  const nlohmann::json provenance = CellProvenanceJson(result, {"", 1});
  EXPECT_EQ(provenance["config_files"]["robot"]["file"], "reachy2.yaml");
  EXPECT_NE(provenance["config_files"]["robot"]["error"].get<std::string>().find("cannot be read"), std::string::npos);
}

TEST(CellProvenance, ServedTimeSplitsWaitingFromTheRest) {
  CellResult result;
  result.config = ServedCellWithOptions();
  result.config.config_dir = TAVIS_CONFIG_DIR;
  result.wall_s = 10.0;
  result.requests = remote::RequestTimings{};
  result.requests->wait_ms = 4000.0;
  result.server_metadata = {Frame({{"checkpoint_sha256", std::string(64, 'A')}}), Frame({{"name", "b"}})};
  const nlohmann::json provenance = CellProvenanceJson(result, {"", 2});
  EXPECT_EQ(provenance["time"]["policy_wait_s"], 4.0);
  EXPECT_EQ(provenance["time"]["simulation_s"], 6.0);
  EXPECT_EQ(provenance["policy"]["server_metadata"][1], nlohmann::json({{"name", "b"}}));
  EXPECT_EQ(provenance["policy"]["checkpoint_sha256"], nlohmann::json({"sha256:" + std::string(64, 'a'), nullptr}));
}

// An observation_contract of the tavis layout, with `extra` fields (docs/serving.md).
Value ContractFrame(Value::Map extra) {
  Value::Map contract = {{"version", 1},
                         {"cameras", Frame({{"head", "observation.images.OBS_HEAD"}})},
                         {"image_width", 96},
                         {"image_height", 96},
                         {"state", Frame({{"key", "observation.state"}, {"size", 34}})},
                         {"n_obs_steps", 1},
                         {"chunk_length", 10},
                         {"executed_steps", 10}};
  for (remote::MapEntry& entry : extra) contract.push_back(std::move(entry));
  return Frame({{"policy", "baseline"}, {"observation_contract", Frame(std::move(contract))}});
}

// What each server's policy was trained for is recorded beside its checkpoint hash, but only in a
// cell where a server declares it: every other cell's summary is as it was.
TEST(CellProvenance, TheTaskAndRobotTrainedForAreRecordedOnlyWhereDeclared) {
  CellResult result;
  result.config = ServedCellWithOptions();
  result.config.config_dir = TAVIS_CONFIG_DIR;
  result.server_metadata = {ContractFrame({}), Frame({{"name", "b"}})};
  EXPECT_FALSE(CellProvenanceJson(result, {"", 2})["policy"].contains("trained_for"));
  result.server_metadata = {ContractFrame({{"task", "conditional-pick"}, {"robot", "gr1t2"}}), Frame({{"name", "b"}}),
                            ContractFrame({{"robot", "gr1t2"}})};
  EXPECT_EQ(CellProvenanceJson(result, {"", 2})["policy"]["trained_for"],
            nlohmann::json::parse(R"([{"task": "conditional-pick", "robot": "gr1t2"}, null, {"robot": "gr1t2"}])"));
  EXPECT_TRUE(DeclaredTrainedFor(ContractFrame({{"task", "Not A Name"}})).is_null()) << "a malformed contract";
  EXPECT_TRUE(DeclaredTrainedFor(Frame({{"task", "conditional-pick"}})).is_null()) << "outside a contract";
}

// The frame is the server's word: a checkpoint hash is taken only when it is 64 hex digits.
TEST(CellProvenance, ACheckpointHashIsTakenOnlyWhenItIsOne) {
  const std::string hex = "0f343b0931126a20f133d67c2b018a3b0f343b0931126a20f133d67c2b018a3b";
  EXPECT_EQ(DeclaredCheckpointSha256(Frame({{"checkpoint_sha256", hex}})), "sha256:" + hex);
  EXPECT_EQ(DeclaredCheckpointSha256(Frame({{"checkpoint_sha256", "sha256:" + hex}})), "sha256:" + hex);
  EXPECT_EQ(DeclaredCheckpointSha256(Frame({{"checkpoint", Frame({{"sha256", hex}})}})), "sha256:" + hex);
  // The reference server declares it inside its observation contract (docs/serving.md).
  EXPECT_EQ(DeclaredCheckpointSha256(Frame({{"observation_contract", Frame({{"checkpoint_sha256", hex}})}})),
            "sha256:" + hex);
  for (const Value& bad : {Frame({{"checkpoint_sha256", hex.substr(1)}}), Frame({{"checkpoint_sha256", hex + "0"}}),
                           Frame({{"checkpoint_sha256", "z" + hex.substr(1)}}), Frame({{"checkpoint_sha256", 12}}),
                           Frame({{"checkpoint", "x"}}), Value("not a map"), Frame({})}) {
    EXPECT_EQ(DeclaredCheckpointSha256(bad), "");
  }
}

// A frame too large for summary.json is recorded by its size, hash and first keys.
TEST(CellProvenance, AHugeMetadataFrameIsRecordedByItsSizeAndHash) {
  Value::Map entries;
  for (int i = 0; i < 100; ++i) entries.push_back({"key" + std::to_string(i), std::string(1000, 'x')});
  const nlohmann::json recorded = RecordedMetadataFrame(Frame(entries));
  EXPECT_GT(recorded.at("json_bytes").get<std::size_t>(), kMaxRecordedMetadataBytes);
  EXPECT_EQ(recorded.at("sha256").get<std::string>().size(), 7u + 64u);
  EXPECT_EQ(recorded.at("keys").size(), 32u);
  EXPECT_LT(recorded.dump().size(), 4096u);
  const nlohmann::json small = RecordedMetadataFrame(Frame({{"name", "tavis test policy"}}));
  EXPECT_EQ(small, nlohmann::json({{"name", "tavis test policy"}}));
}

}  // namespace
}  // namespace tavis::batch::cell
