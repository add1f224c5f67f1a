// The served policy end to end: the episode driver and evaluation cells driven by
// policy_server.py over loopback. Every wait is bounded.
#include "batch/remote/remote_policy.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/cell/cell_report.h"
#include "batch/cell/evaluation_cell.h"
#include "batch/episode_driver.h"
#include "batch/init_pose_warmup.h"
#include "scenarios/registry.h"
#include "tests/batch/remote/policy_server_process.h"
#include "tests/batch/remote/test_scripts.h"
#include "tests/support/robot_loading.h"

namespace tavis::batch::remote {
namespace {

constexpr double kActionScale = 1e-3;  // arm targets within reach, quaternions of any norm

// policy_server.py answering horizon x 19 chunks, scaled to plausible actions.
testing::PolicyServerProcess ServeActions(int horizon, std::vector<std::string> extra = {}, bool wait_ready = true) {
  extra.insert(extra.begin(), {"--horizon", std::to_string(horizon), "--action-dim", "19", "--action-scale", "0.001"});
  return testing::PolicyServerProcess(extra, wait_ready);
}

// The tavis preset's keys, which the tests' requests are read with.
ObservationKeys TavisKeys() { return LoadObservationKeys("tavis", TAVIS_CONFIG_DIR); }

std::uint64_t Uint8Sum(const Value& value) {
  std::uint64_t sum = 0;
  if (const NdArray* array = value.get_if<NdArray>(); array != nullptr && array->dtype == "|u1") {
    for (std::uint8_t byte : array->data) sum += byte;
  }
  if (const Value::Map* map = value.get_if<Value::Map>()) {
    for (const MapEntry& entry : *map) sum += Uint8Sum(entry.value);
  }
  return sum;
}

// policy_server.py's function of a request, in its float64 operation order.
std::vector<double> ExpectedChunk(const Value& request, int horizon) {
  const std::uint64_t image_sum = Uint8Sum(request);
  const std::vector<double> state = FloatArrayToDoubles(request.Find("observation.state")->as<NdArray>("state"));
  const std::string& prompt = request.Find("prompt")->as<std::string>("prompt");
  const double offset = static_cast<double>(image_sum % 1024) / 8 + static_cast<double>(prompt.size()) * 0.25;
  std::vector<double> chunk;
  for (int t = 0; t < horizon; ++t) {
    for (std::size_t d = 0; d < kinematics::action::kSize; ++d) {
      chunk.push_back((state[d % state.size()] * (t + 1) + offset + static_cast<double>(d)) * kActionScale);
    }
  }
  return chunk;
}

// Records what the wrapped served policy was asked with and what it chose, per (episode, policy step).
class RecordingPolicy : public batch::Policy {
 public:
  RecordingPolicy(RemotePolicy& inner, ObservationKeys keys) : inner_(inner), keys_(std::move(keys)) {}
  std::string name() const override { return inner_.name(); }
  int control_ticks_per_action() const override { return inner_.control_ticks_per_action(); }
  std::vector<std::string> cameras() const override { return inner_.cameras(); }
  void Reset(const batch::Observation& observation, const std::vector<uint8_t>& started) override {
    inner_.Reset(observation, started);
  }
  void Act(const batch::Observation& observation, const std::vector<uint8_t>& acting,
           batch::ActionBatch& actions) override {
    inner_.Act(observation, acting, actions);
    for (int env = 0; env < static_cast<int>(acting.size()); ++env) {
      if (!acting[static_cast<std::size_t>(env)]) continue;
      const Key key{observation.state.episode[env], observation.state.control_step[env] / control_ticks_per_action()};
      requests[key] = BuildRequest(observation, keys_, cameras(), env);
      chosen[key] = actions[static_cast<std::size_t>(env)];
    }
  }
  void TakeFaults(std::vector<batch::PolicyFault>& faults) override { inner_.TakeFaults(faults); }

  using Key = std::pair<int64_t, int>;
  std::map<Key, Value> requests;
  std::map<Key, kinematics::Action> chosen;

 private:
  RemotePolicy& inner_;
  ObservationKeys keys_;
};

TEST(RemotePolicy, StepsWithTheServersFunctionOfEachEnvsObservationReplanningEveryKSteps) {
  constexpr int kHorizon = 4;
  constexpr int kReplan = 3;
  testing::PolicyServerProcess first = ServeActions(kHorizon);
  testing::PolicyServerProcess second = ServeActions(kHorizon);
  const scenarios::ScenarioDef& scenario = scenarios::FindScenario("clutter-pick-cube");
  const kinematics::RobotModel robot = tavis::testing::LoadRobot("gr1t2");
  engine::WorldModel model = batch::BuildWorldModel(robot, scenario);
  model.physics.episode_length_s = 1.0;  // 20 policy steps
  batch::VecEnv vec_env(std::move(model), scenario, scenarios::Split::kId, 3, 5);
  RemotePolicyOptions options;
  options.servers = {first.address(), second.address()};
  options.replan_steps = kReplan;
  options.keys = TavisKeys();
  RemotePolicy served(options, vec_env.num_envs());
  RecordingPolicy policy(served, options.keys);
  vec_env.EnableCameras({policy.cameras(), 32, 24, false, false});
  batch::EpisodeDriver driver(vec_env, policy, 4);
  driver.Run();

  ASSERT_FALSE(policy.chosen.empty());
  int queries = 0;
  for (const auto& [key, action] : policy.chosen) {
    const auto [episode, step] = key;
    const int row = step % kReplan;
    const auto request = policy.requests.find({episode, step - row});
    ASSERT_NE(request, policy.requests.end()) << "episode " << episode << " step " << step;
    const std::vector<double> chunk = ExpectedChunk(request->second, kHorizon);
    for (std::size_t d = 0; d < action.size(); ++d) {
      ASSERT_EQ(action[d], chunk[static_cast<std::size_t>(row) * kinematics::action::kSize + d])
          << "episode " << episode << " step " << step << " entry " << d;
    }
    queries += row == 0 ? 1 : 0;
  }
  EXPECT_EQ(static_cast<int>(served.timings().round_trip_ms.size()), queries) << "one request per re-plan, none else";
  EXPECT_EQ(served.timings().server_infer_ms.size(), served.timings().round_trip_ms.size());
}

batch::cell::EvaluationCellConfig ServedCell(const std::vector<std::string>& servers) {
  batch::cell::EvaluationCellConfig config;
  config.task = "clutter-pick-cube";
  config.policy = "openpi";
  config.servers = servers;
  config.episodes = 2;
  config.envs = 2;
  config.seed = 7;
  config.config_dir = TAVIS_CONFIG_DIR;
  config.image_width = 32;
  config.image_height = 24;
  config.keep_actions = true;  // the tests compare every control tick's action
  return config;
}

batch::cell::CellResult RunWithThreads(const batch::cell::EvaluationCellConfig& config, std::size_t threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  return batch::cell::RunEvaluationCell(config);
}

void ExpectSameEpisode(const batch::cell::EpisodeRecord& a, const batch::cell::EpisodeRecord& b,
                       const std::string& what) {
  EXPECT_EQ(a.episode, b.episode) << what;
  EXPECT_EQ(a.success, b.success) << what;
  EXPECT_EQ(a.end, b.end) << what;
  EXPECT_EQ(a.length_control_ticks, b.length_control_ticks) << what;
  EXPECT_EQ(a.solver_messages, b.solver_messages) << what;
  ASSERT_EQ(a.actions.size(), b.actions.size()) << what;
  for (std::size_t t = 0; t < a.actions.size(); ++t)
    ASSERT_EQ(a.actions[t], b.actions[t]) << what << ", control tick " << t;
}

std::filesystem::path FreshDirectory(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("tavis_remote_policy_test_" + name);
  std::filesystem::remove_all(dir);
  return dir;
}

TEST(RemotePolicy, CellIsTheSameWithOneAndTwoThreadsAndItsSavedActionsReplayIt) {
  testing::PolicyServerProcess server = ServeActions(10);
  const batch::cell::EvaluationCellConfig config = ServedCell({server.address()});
  const batch::cell::CellResult one = RunWithThreads(config, 1);
  const batch::cell::CellResult two = RunWithThreads(config, 2);
  ASSERT_EQ(one.episodes.size(), 2U);
  ASSERT_EQ(two.episodes.size(), 2U);
  for (std::size_t i = 0; i < one.episodes.size(); ++i) {
    ExpectSameEpisode(one.episodes[i], two.episodes[i], "1 vs 2 threads, episode " + std::to_string(i));
  }

  const std::filesystem::path dir = FreshDirectory("replay");
  batch::cell::WriteCellReport(two, {2}, dir.string());
  nlohmann::json summary;
  std::ifstream(dir / "summary.json") >> summary;
  EXPECT_EQ(summary["policy"], "openpi");
  EXPECT_GT(summary["requests"]["count"].get<int>(), 0);
  EXPECT_EQ(summary["requests"]["round_trip"]["count"], summary["requests"]["count"]);
  EXPECT_TRUE(summary["requests"]["server_infer"].is_object());

  batch::cell::EvaluationCellConfig replay = config;
  replay.policy = "replay";
  replay.servers.clear();
  replay.episodes = 1;
  replay.actions_file = (dir / "actions" / "episode_0.csv.gz").string();  // one compressed file
  const batch::cell::CellResult replayed = RunWithThreads(replay, 2);
  ASSERT_EQ(replayed.episodes.size(), 1U);
  ExpectSameEpisode(replayed.episodes[0], two.episodes[0], "replay of episode 0's saved actions");
  EXPECT_TRUE(std::filesystem::exists(dir / "actions" / "episode_1.csv.gz"));
  std::filesystem::remove_all(dir);
}

void ExpectContains(const std::string& text, const std::string& part) {
  EXPECT_NE(text.find(part), std::string::npos) << "'" << part << "' not in: " << text;
}

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Acceptance of the serving modes: a server whose answer depends only on the request gives the
// same records whichever way the requests travel, byte for byte in episodes.jsonl and the
// compressed action CSVs.
TEST(RemotePolicy, RecordsAreByteIdenticalServedSeriallyPerEnvAndBatched) {
  testing::PolicyServerProcess server = ServeActions(4, {"--batched"});
  batch::cell::EvaluationCellConfig config = ServedCell({server.address(), server.address()});
  config.episodes = 6;
  config.envs = 4;
  std::map<std::string, std::filesystem::path> written;
  std::map<std::string, batch::cell::CellResult> results;
  for (const ServingMode mode : {ServingMode::kSerial, ServingMode::kPerEnv, ServingMode::kBatched}) {
    config.serving = mode;
    results[ToString(mode)] = RunWithThreads(config, 2);
    const std::filesystem::path dir = FreshDirectory(std::string("mode_") + ToString(mode));
    batch::cell::WriteCellReport(results[ToString(mode)], {2}, dir.string());
    written[ToString(mode)] = dir;
  }
  const batch::cell::CellResult& serial = results["serial"];
  ASSERT_EQ(serial.episodes.size(), 6u);
  for (const char* mode : {"per-env", "batched"}) {
    for (std::size_t i = 0; i < serial.episodes.size(); ++i) {
      ExpectSameEpisode(results[mode].episodes[i], serial.episodes[i],
                        std::string(mode) + ", episode " + std::to_string(i));
    }
    EXPECT_EQ(ReadFile(written[mode] / "episodes.jsonl"), ReadFile(written["serial"] / "episodes.jsonl")) << mode;
    for (int episode = 0; episode < config.episodes; ++episode) {
      const std::string csv = "actions/episode_" + std::to_string(episode) + ".csv.gz";
      ASSERT_TRUE(std::filesystem::exists(written["serial"] / csv)) << csv;
      EXPECT_EQ(ReadFile(written[mode] / csv), ReadFile(written["serial"] / csv)) << mode << " " << csv;
    }
  }
  // Serial and per-env send one env per message; batched sends all envs due at a server together.
  const auto mean_batch = [&](const char* mode) {
    nlohmann::json summary;
    std::ifstream(written[mode] / "summary.json") >> summary;
    EXPECT_EQ(summary["serving"], mode);
    return summary["requests"]["mean_batch_size"].get<double>();
  };
  EXPECT_EQ(mean_batch("serial"), 1.0);
  EXPECT_EQ(mean_batch("per-env"), 1.0);
  EXPECT_GT(mean_batch("batched"), 1.0) << "two envs per server at the same policy tick";
  EXPECT_LT(results["batched"].requests->round_trip_ms.size(), serial.requests->round_trip_ms.size());
  for (const auto& [mode, dir] : written) std::filesystem::remove_all(dir);
}

// A stateful server must see every episode's policy steps in order, the first flagged, however
// many envs run at once; the records do not depend on the env count.
TEST(RemotePolicy, AStatefulServerSeesEachEpisodesStepsInOrderWithSixteenEnvsAsWithOne) {
  std::map<int, batch::cell::CellResult> results;
  for (const int envs : {16, 1}) {
    const std::filesystem::path steps = FreshDirectory("steps_" + std::to_string(envs) + ".json");
    batch::cell::CellResult result;
    {
      testing::PolicyServerProcess server = ServeActions(1, {"--check-steps", "--steps-out", steps.string()});
      batch::cell::EvaluationCellConfig config = ServedCell({server.address()});
      config.episodes = 16;
      config.envs = envs;
      config.serving = envs > 1 ? ServingMode::kPerEnv : ServingMode::kSerial;
      result = RunWithThreads(config, 2);
    }  // the server writes what it saw when it stops
    nlohmann::json seen;
    std::ifstream(steps) >> seen;
    ASSERT_EQ(result.episodes.size(), 16u);
    int listed = 0;
    for (const auto& [key, entry] : seen.items()) {
      const int64_t episode = std::stoll(key.substr(key.find('/') + 1));
      EXPECT_EQ(entry["first_flags"], 1) << key;
      // The episode asked at every policy step it acted on: its length in steps (the step that
      // ended it acted too).
      EXPECT_EQ(entry["steps"].get<int>(), result.episodes[static_cast<std::size_t>(episode)].length_steps) << key;
      ++listed;
    }
    EXPECT_EQ(listed, 16) << "one (env, episode) entry per episode";
    std::filesystem::remove(steps);
    results[envs] = std::move(result);
  }
  for (std::size_t i = 0; i < 16; ++i) {
    ExpectSameEpisode(results[16].episodes[i], results[1].episodes[i], "16 vs 1 envs, episode " + std::to_string(i));
  }
}

// Under ood-init-pose the reset holds a warm-up action for 10 policy steps before the policy's
// first observation: that observation is still step 0 and flagged first, so a stateful server
// sees every episode start (the episode's length counts the warm-up).
TEST(RemotePolicy, AStatefulServerSeesStepZeroFirstAfterTheInitPoseWarmUp) {
  const std::filesystem::path steps = FreshDirectory("steps_init_pose.json");
  batch::cell::CellResult result;
  {
    testing::PolicyServerProcess server = ServeActions(1, {"--check-steps", "--steps-out", steps.string()});
    batch::cell::EvaluationCellConfig config = ServedCell({server.address()});
    config.split = scenarios::Split::kOodInitPose;
    config.episodes = 4;
    config.envs = 4;
    config.serving = ServingMode::kPerEnv;
    result = RunWithThreads(config, 2);
  }
  nlohmann::json seen;
  std::ifstream(steps) >> seen;
  ASSERT_EQ(result.episodes.size(), 4u);
  ASSERT_EQ(seen.size(), 4u) << seen.dump();
  for (const auto& [key, entry] : seen.items()) {
    const int64_t episode = std::stoll(key.substr(key.find('/') + 1));
    EXPECT_EQ(entry["first_flags"], 1) << key;
    EXPECT_EQ(entry["steps"].get<int>(),
              result.episodes[static_cast<std::size_t>(episode)].length_steps - batch::kInitPoseWarmupPolicySteps)
        << key;
  }
  std::filesystem::remove(steps);
}

TEST(RemotePolicy, AServerWithoutHealthzIsConnectedToDirectly) {
  testing::PolicyServerProcess server = ServeActions(10, {"--no-healthz"}, /*wait_ready=*/false);
  batch::cell::EvaluationCellConfig config = ServedCell({server.address()});
  config.episodes = 1;
  config.envs = 1;
  const batch::cell::CellResult result = RunWithThreads(config, 2);
  ASSERT_EQ(result.episodes.size(), 1u);
  EXPECT_GT(result.requests->round_trip_ms.size(), 0u);
}

TEST(RemotePolicy, BatchedServingNeedsAServerThatDeclaresIt) {
  testing::PolicyServerProcess server = ServeActions(4);
  batch::cell::EvaluationCellConfig config = ServedCell({server.address()});
  config.serving = ServingMode::kBatched;
  try {
    batch::cell::RunEvaluationCell(config);
    ADD_FAILURE() << "batched requests sent to a server that does not declare them";
  } catch (const std::invalid_argument& error) {
    ExpectContains(error.what(), "does not declare \"batched_requests\": true");
    ExpectContains(error.what(), server.address());
  }
}

std::string FailureOf(const batch::cell::EvaluationCellConfig& config) {
  try {
    batch::cell::RunEvaluationCell(config);
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  ADD_FAILURE() << "the cell did not fail";
  return "";
}

TEST(RemotePolicy, ServerErrorStopsTheCellWithTheTracebackNamingTheEnvAndEpisode) {
  testing::PolicyServerProcess server = ServeActions(10, {"--fail-at-request", "1"});
  const std::string message = FailureOf(ServedCell({server.address()}));
  ExpectContains(message, "policy 'openpi', env slot 1 (episode 1, server " + server.address() + ")");
  ExpectContains(message, "Traceback (most recent call last)");
  ExpectContains(message, "RuntimeError: test policy asked to fail at request 1");
}

// Every episode of the cell ended invalid_action with a reason containing `reason` (and `entry`).
void ExpectEveryEpisodeInvalid(const batch::cell::CellResult& result, const std::string& reason, int entry) {
  ASSERT_EQ(result.episodes.size(), 2U) << "the cell went on to its last episode";
  for (const batch::cell::EpisodeRecord& record : result.episodes) {
    EXPECT_EQ(record.end, engine::EpisodeEnd::kInvalidAction) << "episode " << record.episode;
    EXPECT_EQ(record.invalid_action.entry, entry) << "episode " << record.episode;
    ExpectContains(record.invalid_action.reason, reason);
  }
}

TEST(RemotePolicy, ChunkOfTheWrongWidthEndsEachEpisodeInvalidNamingTheShape) {
  testing::PolicyServerProcess server({"--horizon", "10", "--action-dim", "7"});
  const batch::cell::CellResult result = batch::cell::RunEvaluationCell(ServedCell({server.address()}));
  ExpectEveryEpisodeInvalid(result, "server " + server.address() + ": reply actions are 10 x 7, expected H x 19", -1);
  ExpectContains(batch::cell::CellSummaryLine(result), "2 ended invalid_action (first: episode 0: server");
}

TEST(RemotePolicy, ChunkOfAnIntegerDtypeEndsEachEpisodeInvalidNamingTheDtype) {
  testing::PolicyServerProcess server = ServeActions(10, {"--actions-dtype", "<i8"});
  const batch::cell::CellResult result = batch::cell::RunEvaluationCell(ServedCell({server.address()}));
  ExpectEveryEpisodeInvalid(result, "<i8", -1);
}

TEST(RemotePolicy, NonFiniteActionEndsItsEpisodeNamingTheEntryAndTheRecordSaysSo) {
  testing::PolicyServerProcess server = ServeActions(10, {"--nan-entry", "5"});
  const batch::cell::CellResult result = batch::cell::RunEvaluationCell(ServedCell({server.address()}));
  ExpectEveryEpisodeInvalid(result, "not finite", 5);
  const std::filesystem::path dir = FreshDirectory("nan");
  batch::cell::WriteCellReport(result, {1}, dir.string());
  std::ifstream episodes(dir / "episodes.jsonl");
  std::string line;
  ASSERT_TRUE(std::getline(episodes, line));
  const nlohmann::json record = nlohmann::json::parse(line);
  EXPECT_EQ(record["end"], "invalid_action");
  EXPECT_EQ(record["invalid_action"], nlohmann::json({{"entry", 5}, {"value", "nan"}, {"reason", "not finite"}}));
  nlohmann::json summary;
  std::ifstream(dir / "summary.json") >> summary;
  EXPECT_EQ(summary["ends"], nlohmann::json({{"invalid_action", 2}}));
  std::filesystem::remove_all(dir);
}

TEST(RemotePolicy, LayoutsAndTheServersMetadataAreRecordedInTheSummary) {
  testing::PolicyServerProcess server = ServeActions(10);
  batch::cell::EvaluationCellConfig config = ServedCell({server.address()});
  config.observation_keys = "aloha";
  config.image_width = 40;
  config.image_height = 40;
  const batch::cell::CellResult result = batch::cell::RunEvaluationCell(config);
  EXPECT_EQ(result.render_width, 40);
  EXPECT_EQ(result.render_height, 30) << "letterboxed: the 4:3 cameras fitted into 40 x 40";
  const std::filesystem::path dir = FreshDirectory("layout");
  batch::cell::WriteCellReport(result, {1}, dir.string());
  nlohmann::json summary;
  std::ifstream(dir / "summary.json") >> summary;
  EXPECT_EQ(summary["observation_keys"], "aloha");
  EXPECT_EQ(summary["policy_image"], nlohmann::json({{"width", 40}, {"height", 40}}));
  EXPECT_EQ(summary["render"]["height"], 30);
  ASSERT_EQ(summary["server_metadata"].size(), 1U);
  EXPECT_EQ(summary["server_metadata"][0]["server"], "tavis test policy");
  EXPECT_EQ(summary["server_metadata"][0]["action_dim"], 19);
  std::filesystem::remove_all(dir);
}

// Each episode's time split (cell/episode_times.h): a served cell waits for its server, and the
// episodes' shares of the policy's calls cover at least the time spent waiting for replies.
TEST(RemotePolicy, EveryEpisodeOfAServedCellWaitsForThePolicy) {
  testing::PolicyServerProcess server = ServeActions(10, {"--sleep-ms", "5"});
  const batch::cell::CellResult result = RunWithThreads(ServedCell({server.address()}), 2);
  ASSERT_EQ(result.episodes.size(), 2U);
  ASSERT_TRUE(result.requests.has_value());
  double policy_s = 0.0;
  for (const batch::cell::EpisodeRecord& record : result.episodes) {
    ASSERT_TRUE(record.times.has_value()) << "episode " << record.episode;
    EXPECT_GT(record.times->part(batch::cell::EpisodeTimes::kPolicy), 0.0) << "episode " << record.episode;
    EXPECT_EQ(record.times->part(batch::cell::EpisodeTimes::kVideo), 0.0) << "episode " << record.episode;
    policy_s += record.times->part(batch::cell::EpisodeTimes::kPolicy);
  }
  EXPECT_GE(policy_s, result.requests->wait_ms / 1000.0 - 1e-6);
  EXPECT_GT(result.requests->wait_ms, 0.0);
}

TEST(RemotePolicy, ServerDyingMidCellStopsItNamingTheServer) {
  // The server exits half a second after it listens; four 20 s episodes take several seconds.
  testing::PolicyServerProcess server = ServeActions(10, {"--lifetime", "0.5"});
  batch::cell::EvaluationCellConfig config = ServedCell({server.address()});
  config.episodes = 4;
  config.server_ready_timeout_s = 1.0;
  const std::string message = FailureOf(config);
  ExpectContains(message, server.address());
}

TEST(RemotePolicy, UnreachableServerFailsWithinTheReadyTimeoutNamingIt) {
  batch::cell::EvaluationCellConfig config =
      ServedCell({"ws://127.0.0.1:" + std::to_string(testing::FreeLoopbackPort())});
  config.server_ready_timeout_s = 1.0;
  const auto start = std::chrono::steady_clock::now();
  const std::string message = FailureOf(config);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
  ExpectContains(message, "policy server " + config.servers[0] + " is not reachable");
}

TEST(RemotePolicy, ConfigurationMistakesAreNamed) {
  batch::cell::EvaluationCellConfig config = ServedCell({});
  EXPECT_THROW(
      {
        try {
          batch::cell::RunEvaluationCell(config);
        } catch (const std::invalid_argument& error) {
          ExpectContains(error.what(), "servers must name a policy server");
          throw;
        }
      },
      std::invalid_argument);
  config.policy = "hold";
  config.servers = {"ws://127.0.0.1:1"};
  EXPECT_THROW(batch::cell::RunEvaluationCell(config), std::invalid_argument);
  config.policy = "pi0";
  config.servers.clear();
  try {
    batch::cell::RunEvaluationCell(config);
    ADD_FAILURE() << "unknown policy accepted";
  } catch (const std::invalid_argument& error) {
    ExpectContains(error.what(), "unknown policy 'pi0' (known: expert, hold, replay, openpi)");
  }
}

}  // namespace
}  // namespace tavis::batch::remote
