// The served policy's request layouts: the shipped presets, the YAML schema's errors, letterboxing,
// and the layout as Python's msgpack-numpy decodes it (policy_server.py echoes what it received).
#include "batch/remote/observation_keys.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/proprioception.h"
#include "batch/remote/openpi_session.h"
#include "batch/vec_env.h"
#include "configs/robot_config.h"
#include "configs/yaml_reader.h"
#include "scenarios/registry.h"
#include "tests/batch/remote/policy_server_process.h"
#include "tests/support/robot_loading.h"

namespace tavis::batch::remote {
namespace {

ObservationKeys Preset(const std::string& name) { return LoadObservationKeys(name, TAVIS_CONFIG_DIR); }

TEST(ObservationKeys, PresetsNameTheirCamerasAndTheFixedCameraTakesHeadsPlaceOrItsOwnKey) {
  const ObservationKeys tavis = Preset("tavis");
  EXPECT_EQ(tavis.PolicyCameras(), (std::vector<std::string>{"head", "left_wrist", "right_wrist"}));
  EXPECT_EQ(tavis.KeyOf("head"), KeyPath{"observation.images.OBS_HEAD"}) << "the dataset's key (tavis demos)";
  EXPECT_EQ(tavis.KeyOf("fixed"), KeyPath{"observation.images.OBS_FIXED"});
  EXPECT_EQ(tavis.KeyOf("left_wrist"), KeyPath{"observation.images.OBS_WRIST_LEFT"});
  EXPECT_EQ(tavis.KeyOf("right_wrist"), KeyPath{"observation.images.OBS_WRIST_RIGHT"});
  EXPECT_EQ(tavis.state, KeyPath{"observation.state"});
  EXPECT_EQ(tavis.prompt, KeyPath{"prompt"});
  EXPECT_EQ(tavis.task, KeyPath{"task"}) << "LeRobot reads the instruction as task";
  EXPECT_FALSE(tavis.letterbox);
  EXPECT_EQ(RenderSize(tavis), (std::pair<int, int>{320, 240})) << "the reference's evaluation size";

  const ObservationKeys libero = Preset("libero");
  EXPECT_EQ(libero.PolicyCameras(), (std::vector<std::string>{"head", "right_wrist"}));
  EXPECT_EQ(libero.KeyOf("fixed"), KeyPath{"observation/image"});
  EXPECT_EQ(RenderSize(libero), (std::pair<int, int>{224, 168})) << "openpi's resize_with_pad of 640x480 into 224x224";
  EXPECT_THROW(libero.KeyOf("left_wrist"), std::logic_error);

  const ObservationKeys aloha = Preset("aloha");
  EXPECT_EQ(aloha.KeyOf("left_wrist"), (KeyPath{"images", "cam_left_wrist"}));
  EXPECT_EQ(aloha.image_layout, ImageLayout::kChw);
}

class KeyFile : public ::testing::Test {
 protected:
  // Loads `text` as a key file and returns the error it raises, or "" when it loads.
  std::string ErrorOf(const std::string& text) {
    const std::filesystem::path path = std::filesystem::temp_directory_path() / "tavis_observation_keys_test.yaml";
    std::ofstream(path) << text;
    try {
      LoadObservationKeys(path.string(), TAVIS_CONFIG_DIR);
    } catch (const configs::ConfigError& error) {
      return error.what();
    }
    return "";
  }

  static std::string Valid(const std::string& cameras, const std::string& rest = "") {
    return "cameras:\n" + cameras +
           "state: s\nprompt: p\nimage_layout: hwc\nimage_width: 64\nimage_height: 48\nletterbox: false\n" + rest;
  }
};

TEST_F(KeyFile, ALayoutOfTheUsersOwnLoads) {
  EXPECT_EQ(ErrorOf(Valid("  head: [obs, front]\n  left_wrist: wrist\n")), "");
}

TEST_F(KeyFile, ALayoutMayNotUseTheRequestFieldsKeys) {
  for (const char* field : {"env_index", "episode_index", "step", "is_first", "batch_size"}) {
    EXPECT_NE(ErrorOf(Valid(std::string("  head: ") + field + "\n")).find("request field"), std::string::npos) << field;
  }
  EXPECT_NE(ErrorOf(Valid("  head: a\n", "task: [step, x]\n")).find("'step'"), std::string::npos);
}

TEST_F(KeyFile, EachMistakeIsNamedWithItsKey) {
  EXPECT_NE(ErrorOf(Valid("  head: a\n  chest: b\n")).find("chest"), std::string::npos);
  EXPECT_NE(ErrorOf(Valid("  head: a\n", "extra: 1\n")).find("extra"), std::string::npos);
  EXPECT_NE(ErrorOf(Valid("  fixed: a\n")).find("give head a key too"), std::string::npos);
  EXPECT_NE(ErrorOf(Valid("  {}\n")).find("no camera for the policy"), std::string::npos);
  EXPECT_NE(ErrorOf(Valid("  head: a\n  left_wrist: a\n")).find("head and left_wrist overlap at key 'a'"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Valid("  head: [obs, img]\n  left_wrist: obs\n")).find("overlap"), std::string::npos);
  EXPECT_NE(ErrorOf(Valid("  head: ''\n")).find("empty key"), std::string::npos);
  EXPECT_NE(ErrorOf(Valid("  head: []\n")).find("at least one key"), std::string::npos);
  std::string layout = Valid("  head: a\n");
  layout.replace(layout.find("hwc"), 3, "whc");
  EXPECT_NE(ErrorOf(layout).find("image_layout: expected hwc or chw, got 'whc'"), std::string::npos);
  std::string size = Valid("  head: a\n");
  size.replace(size.find("64"), 2, "0");
  EXPECT_NE(ErrorOf(size).find("at least 8"), std::string::npos);
  EXPECT_THROW(LoadObservationKeys("pi0-droid", TAVIS_CONFIG_DIR), std::invalid_argument);
}

// One env of clutter-pick-cube at its reset, rendered and observed as the episode driver does.
class RenderedObservation : public ::testing::Test {
 protected:
  RenderedObservation()
      : robot_(tavis::testing::LoadRobot("gr1t2")),
        env_(batch::BuildWorldModel(robot_, scenarios::FindScenario("clutter-pick-cube")),
             scenarios::FindScenario("clutter-pick-cube"), scenarios::Split::kId, 2, 3),
        proprioception_(env_.model().robot, 2),
        prompts_{nullptr, nullptr} {}

  // Slot s runs episode s.
  batch::Observation Observe(const std::vector<std::string>& cameras, int width, int height) {
    env_.EnableCameras({cameras, width, height, false, false});
    for (int slot = 0; slot < 2; ++slot) env_.ResetEnv(slot, slot);
    env_.RenderPolicyTick();
    proprioception_.Update(env_.state(), {1, 1});
    for (int slot = 0; slot < 2; ++slot) prompts_[slot] = env_.scenario().prompt(env_.state(), slot);
    return batch::Observation{env_.model(), env_.state(), env_.images(), prompts_, &proprioception_};
  }

  kinematics::RobotModel robot_;
  batch::VecEnv env_;
  batch::ProprioceptionBatch proprioception_;
  std::vector<const char*> prompts_;
};

TEST_F(RenderedObservation, AlohaNestsChannelFirstLetterboxedImages) {
  const ObservationKeys keys = Preset("aloha");
  const batch::Observation observation = Observe({"head", "left_wrist", "right_wrist"}, 40, 30);
  ObservationKeys sized = keys;
  sized.image_width = 40;
  sized.image_height = 40;
  const Value request = BuildRequest(observation, sized, {"head", "left_wrist", "right_wrist"}, 0);
  const Value* images = request.Find("images");
  ASSERT_NE(images, nullptr);
  const NdArray& high = images->Find("cam_high")->as<NdArray>("cam_high");
  EXPECT_EQ(high.shape, (std::vector<std::int64_t>{3, 40, 40}));
  const uint8_t* rendered = observation.images->rgb(0, 0);
  long long band_sum = 0, differences = 0;
  for (int c = 0; c < 3; ++c) {
    for (int y = 0; y < 40; ++y) {
      for (int x = 0; x < 40; ++x) {
        const uint8_t sent = high.data[static_cast<std::size_t>((c * 40 + y) * 40 + x)];
        if (y < 5 || y >= 35) {
          band_sum += sent;
        } else {
          differences += sent != rendered[((y - 5) * 40 + x) * 3 + c];
        }
      }
    }
  }
  EXPECT_EQ(band_sum, 0) << "5 black rows above and below the 40 x 30 image";
  EXPECT_EQ(differences, 0) << "the rendered pixels, channel first";
  EXPECT_NE(request.Find("state"), nullptr);
  EXPECT_EQ(request.Find("prompt")->as<std::string>("prompt"), std::string(prompts_[0]));
}

TEST_F(RenderedObservation, ARequestCarriesTheEnvTheEpisodeTheStepAndTheFirstFlag) {
  const batch::Observation observation = Observe({"head", "left_wrist", "right_wrist"}, 32, 24);
  const Value request = BuildRequest(observation, Preset("tavis"), {"head", "left_wrist", "right_wrist"}, 1);
  EXPECT_EQ(*request.Find("env_index"), Value(1));
  EXPECT_EQ(*request.Find("episode_index"), Value(1));
  EXPECT_EQ(*request.Find("step"), Value(0));
  EXPECT_EQ(*request.Find("is_first"), Value(true));
  EXPECT_EQ(*request.Find("task"), *request.Find("prompt"));
  EXPECT_EQ(request.Find("batch_size"), nullptr);
}

TEST_F(RenderedObservation, ABatchedRequestStacksEachEnvsRequestOnALeadingAxis) {
  const std::vector<std::string> cameras = {"head", "left_wrist", "right_wrist"};
  const batch::Observation observation = Observe(cameras, 32, 24);
  const ObservationKeys keys = Preset("tavis");
  const Value batched = BuildBatchRequest(observation, keys, cameras, {0, 1});
  EXPECT_EQ(*batched.Find("batch_size"), Value(2));
  for (const char* key : {"observation.images.OBS_HEAD", "observation.images.OBS_WRIST_LEFT",
                          "observation.images.OBS_WRIST_RIGHT", "observation.state"}) {
    const NdArray& stacked = batched.Find(key)->as<NdArray>(key);
    ASSERT_EQ(stacked.shape.front(), 2) << key;
    std::vector<std::uint8_t> concatenated;
    for (int env : {0, 1}) {
      const Value request = BuildRequest(observation, keys, cameras, env);
      const NdArray& single = request.Find(key)->as<NdArray>(key);
      EXPECT_EQ(std::vector<std::int64_t>(stacked.shape.begin() + 1, stacked.shape.end()), single.shape) << key;
      concatenated.insert(concatenated.end(), single.data.begin(), single.data.end());
    }
    EXPECT_EQ(stacked.data, concatenated) << key;
  }
  const auto int64s = [&](const char* key) {
    const NdArray& array = batched.Find(key)->as<NdArray>(key);
    EXPECT_EQ(array.dtype, "<i8") << key;
    std::vector<std::int64_t> values(array.data.size() / 8);
    std::memcpy(values.data(), array.data.data(), array.data.size());
    return values;
  };
  EXPECT_EQ(int64s("env_index"), (std::vector<std::int64_t>{0, 1}));
  EXPECT_EQ(int64s("episode_index"), (std::vector<std::int64_t>{0, 1}));
  EXPECT_EQ(int64s("step"), (std::vector<std::int64_t>{0, 0}));
  const NdArray& first = batched.Find("is_first")->as<NdArray>("is_first");
  EXPECT_EQ(first.dtype, "|b1");
  EXPECT_EQ(first.data, (std::vector<std::uint8_t>{1, 1}));
  const Value::Array& prompts = batched.Find("prompt")->as<Value::Array>("prompt");
  ASSERT_EQ(prompts.size(), 2u);
  EXPECT_EQ(prompts[1], Value(prompts_[1]));
  EXPECT_EQ(*batched.Find("task"), *batched.Find("prompt"));
}

// A dataset's meta/info.json as `tavis demos` writes it, trimmed to what the layout reads.
std::filesystem::path WriteDatasetInfo(const std::string& name, const nlohmann::json& features) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / name;
  std::filesystem::create_directories(dir / "meta");
  std::ofstream(dir / "meta" / "info.json")
      << nlohmann::json{{"codebase_version", "v3.0"}, {"features", features}}.dump();
  return dir;
}

nlohmann::json ImageFeature(int width, int height) {
  return {{"dtype", "video"}, {"shape", {height, width, 3}}, {"names", {"height", "width", "channels"}}};
}

TEST(DatasetKeys, TheDatasetsImageKeysAndSizeAreServedAndDifferencesAreNamed) {
  const nlohmann::json state = {{"dtype", "float32"}, {"shape", {34}}};
  const std::filesystem::path dir =
      WriteDatasetInfo("tavis_dataset_keys_test", {{"observation.state", state},
                                                   {"observation.images.OBS_HEAD", ImageFeature(64, 48)},
                                                   {"observation.images.OBS_FIXED", ImageFeature(64, 48)},
                                                   {"observation.images.OBS_WRIST_LEFT", ImageFeature(64, 48)},
                                                   {"observation.images.OBS_WRIST_RIGHT", ImageFeature(64, 48)}});
  const ObservationKeys keys = LoadDatasetKeys(dir.string(), 34);
  EXPECT_EQ(keys.PolicyCameras(), (std::vector<std::string>{"head", "left_wrist", "right_wrist"}));
  EXPECT_EQ(keys.KeyOf("fixed"), KeyPath{"observation.images.OBS_FIXED"});
  EXPECT_EQ(keys.image_width, 64);
  EXPECT_EQ(keys.image_height, 48);
  EXPECT_TRUE(LayoutDifferences(keys, keys).empty());

  const std::vector<std::string> differences = LayoutDifferences(Preset("tavis"), keys);
  ASSERT_EQ(differences.size(), 1u);
  EXPECT_NE(differences[0].find("image size: served 320x240"), std::string::npos) << differences[0];
  EXPECT_NE(differences[0].find("64x48"), std::string::npos) << differences[0];
  EXPECT_GE(LayoutDifferences(Preset("libero"), keys).size(), 4u) << "cameras, state, and letterbox all differ";

  try {
    LoadDatasetKeys(dir.string(), 19);
    ADD_FAILURE() << "a Reachy2 state size must not match a GR1T2 dataset";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("observation.state has 34 entries, but this robot's has 19"),
              std::string::npos)
        << error.what();
  }
  EXPECT_THROW(LoadDatasetKeys((dir / "nowhere").string(), 34), std::invalid_argument);
  const std::filesystem::path no_images =
      WriteDatasetInfo("tavis_dataset_keys_test_no_images", {{"observation.state", state}});
  EXPECT_THROW(LoadDatasetKeys(no_images.string(), 34), std::invalid_argument);
}

TEST_F(RenderedObservation, PythonDecodesEachPresetsLayout) {
  testing::PolicyServerProcess server({"--horizon", "1", "--action-dim", "19"});
  OpenpiSessionOptions options;
  options.url = server.address();
  OpenpiSession session(options);
  const batch::Observation observation = Observe({"fixed", "right_wrist", "left_wrist"}, 32, 24);
  struct Case {
    std::string preset;
    std::vector<std::string> cameras;  // the first images of the observation, under the fixed protocol
    std::map<std::string, nlohmann::json> expected;
  };
  const std::vector<Case> cases = {
      {"tavis",
       {"fixed", "right_wrist", "left_wrist"},
       {{"observation.images.OBS_FIXED", {"|u1", {24, 32, 3}}},
        {"observation.images.OBS_WRIST_LEFT", {"|u1", {24, 32, 3}}},
        {"observation.images.OBS_WRIST_RIGHT", {"|u1", {24, 32, 3}}},
        {"observation.state", {"<f4", {34}}},
        {"prompt", "str"},
        {"task", "str"}}},
      {"libero",
       {"fixed", "right_wrist"},
       {{"observation/image", {"|u1", {24, 32, 3}}},
        {"observation/wrist_image", {"|u1", {24, 32, 3}}},
        {"observation/state", {"<f4", {34}}},
        {"prompt", "str"}}},
      {"aloha",
       {"fixed", "right_wrist", "left_wrist"},
       {{"images|cam_high", {"|u1", {3, 24, 32}}},
        {"images|cam_left_wrist", {"|u1", {3, 24, 32}}},
        {"images|cam_right_wrist", {"|u1", {3, 24, 32}}},
        {"state", {"<f4", {34}}},
        {"prompt", "str"}}},
  };
  for (Case test : cases) {
    // Every layout carries the request fields at its top level.
    test.expected.insert({{"env_index", "int"}, {"episode_index", "int"}, {"step", "int"}, {"is_first", "bool"}});
    ObservationKeys keys = Preset(test.preset);
    keys.letterbox = false;
    const Value request = BuildRequest(observation, keys, test.cameras, 0);
    const InferResult result = session.Infer(request);
    std::map<std::string, nlohmann::json> received;
    for (const MapEntry& entry : result.reply.Find("received")->as<Value::Map>("received")) {
      const std::string& key = entry.key.as<std::string>("key");
      if (const std::string* text = entry.value.get_if<std::string>()) {
        received[key] = *text;
      } else {
        const Value::Array& pair = entry.value.as<Value::Array>("pair");
        nlohmann::json shape = nlohmann::json::array();
        for (const Value& dimension : pair[1].as<Value::Array>("shape"))
          shape.push_back(dimension.as<std::int64_t>("dim"));
        received[key] = {pair[0].as<std::string>("dtype"), shape};
      }
    }
    EXPECT_EQ(received, test.expected) << test.preset;
  }
}

}  // namespace
}  // namespace tavis::batch::remote
