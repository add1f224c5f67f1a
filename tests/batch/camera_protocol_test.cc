#include "batch/camera_protocol.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "batch/builtin_policies.h"
#include "batch/episode_driver.h"
#include "scenarios/registry.h"
#include "tests/support/altered_hold_policy.h"
#include "tests/support/robot_loading.h"

namespace tavis::batch {
namespace {

TEST(CameraProtocol, ParsesTheReferenceSpellingsAndNamesABadValue) {
  EXPECT_EQ(ParseCameraProtocol("head"), CameraProtocol::kHead);
  EXPECT_EQ(ParseCameraProtocol("fixedcam"), CameraProtocol::kFixed);
  EXPECT_STREQ(ToString(ParseCameraProtocol("headcam")), "head");
  try {
    ParseCameraProtocol("side");
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("'side'"), std::string::npos) << error.what();
  }
}

TEST(CameraProtocol, FixedGivesTheFixedCameraForTheHeadAndZeroesTheNeckActions) {
  const std::vector<std::string> policy = {"head", "left_wrist", "right_wrist"};
  EXPECT_EQ(ProtocolCameras(policy, CameraProtocol::kHead), policy);
  EXPECT_EQ(ProtocolCameras(policy, CameraProtocol::kFixed),
            (std::vector<std::string>{"fixed", "left_wrist", "right_wrist"}));
  kinematics::Action action;
  action.fill(0.5);
  ApplyToAction(CameraProtocol::kHead, action);
  EXPECT_EQ(action[kinematics::action::kNeckYaw], 0.5);
  ApplyToAction(CameraProtocol::kFixed, action);
  for (int i = 0; i < kinematics::action::kSize; ++i) {
    const bool neck = i >= kinematics::action::kNeckRoll && i <= kinematics::action::kNeckYaw;
    EXPECT_EQ(action[i], neck ? 0.0 : 0.5) << "entry " << i;
  }
}

TEST(CameraProtocol, CameraSetsKeepOneViewAndBlackOutTheRest) {
  for (const std::string& name : CameraProtocolNames()) EXPECT_EQ(ToString(ParseCameraProtocol(name)), name);
  EXPECT_EQ(CameraProtocolNames().size(), 5u);
  const std::vector<std::string> policy = {"head", "left_wrist", "right_wrist"};
  const std::vector<std::string> wrists = {"left_wrist", "right_wrist"};
  EXPECT_EQ(ProtocolCameras(policy, CameraProtocol::kHeadOnly), policy);
  EXPECT_EQ(ProtocolCameras(policy, CameraProtocol::kWristsOnly), policy) << "the head image is sent, black";
  EXPECT_EQ(ProtocolCameras(policy, CameraProtocol::kFixedOnly),
            (std::vector<std::string>{"fixed", "left_wrist", "right_wrist"}));
  EXPECT_EQ(ProtocolBlackCameras(CameraProtocol::kHead), std::vector<std::string>{});
  EXPECT_EQ(ProtocolBlackCameras(CameraProtocol::kFixed), std::vector<std::string>{});
  EXPECT_EQ(ProtocolBlackCameras(CameraProtocol::kHeadOnly), wrists);
  EXPECT_EQ(ProtocolBlackCameras(CameraProtocol::kFixedOnly), wrists);
  EXPECT_EQ(ProtocolBlackCameras(CameraProtocol::kWristsOnly), std::vector<std::string>{"head"});
  kinematics::Action action;
  action.fill(0.5);
  ApplyToAction(CameraProtocol::kWristsOnly, action);
  ApplyToAction(CameraProtocol::kHeadOnly, action);
  EXPECT_EQ(action[kinematics::action::kNeckYaw], 0.5) << "the head moves under head-only and wrists-only";
  ApplyToAction(CameraProtocol::kFixedOnly, action);
  EXPECT_EQ(action[kinematics::action::kNeckYaw], 0.0);
  EXPECT_FALSE(UsesFixedView(CameraProtocol::kWristsOnly));
  EXPECT_TRUE(UsesFixedView(CameraProtocol::kFixedOnly));
}

// Per episode: the object poses at its start and the largest neck angle reached.
class NeckAndLayout : public EpisodeSink {
 public:
  void EpisodeStarted(const VecEnv& vec_env, int slot) override {
    const engine::BatchState& state = vec_env.state();
    layouts.emplace_back(state.object_pose_row(slot, 0),
                         state.object_pose_row(slot, 0) + engine::kObjectPoseSize * state.num_objects);
  }
  void Stepped(const VecEnv& vec_env) override {
    for (int slot = 0; slot < vec_env.num_envs(); ++slot) {
      for (int joint : vec_env.model().robot.neck_joints) {
        largest_neck = std::max(largest_neck, std::abs(vec_env.state().q_row(slot)[joint]));
      }
    }
  }
  std::vector<std::vector<double>> layouts;  // in start order
  double largest_neck = 0.0;
};

NeckAndLayout RunProtocol(CameraProtocol protocol) {
  const scenarios::ScenarioDef& scenario = scenarios::FindScenario("conditional-pick");
  const kinematics::RobotModel robot = tavis::testing::LoadRobot("gr1t2");
  engine::WorldModel model = BuildWorldModel(robot, scenario);
  model.physics.episode_length_s = 1.0;
  VecEnv vec_env(std::move(model), scenario, scenarios::Split::kId, 2, 11);
  // The hold policy with the head pitched and turned: a policy that moves its head.
  testing::AlteredHoldPolicy policy(vec_env, "look-around", 3, [](const Observation&, int, kinematics::Action& action) {
    action[kinematics::action::kNeckPitch] = 0.4;
    action[kinematics::action::kNeckYaw] = -0.6;
  });
  NeckAndLayout sink;
  EpisodeDriver driver(vec_env, policy, 3);
  driver.AddSink(sink);
  driver.SetCameraProtocol(protocol);
  driver.Run();
  return sink;
}

TEST(CameraProtocol, UnderFixedTheNeckStaysStillWhateverThePolicySendsAndEpisodesPair) {
  const NeckAndLayout head = RunProtocol(CameraProtocol::kHead);
  const NeckAndLayout fixed = RunProtocol(CameraProtocol::kFixed);
  EXPECT_GT(head.largest_neck, 0.3) << "under head the neck follows the policy";
  EXPECT_EQ(fixed.largest_neck, 0.0) << "under fixed the neck does not move";
  ASSERT_EQ(head.layouts.size(), 3u);
  EXPECT_EQ(head.layouts, fixed.layouts) << "episode i has the same scene under both protocols";
}

}  // namespace
}  // namespace tavis::batch
