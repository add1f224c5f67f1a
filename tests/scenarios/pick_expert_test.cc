// The pick expert's grasp decisions, run kinematically: the expert steps on its own commands
// (its phases advance on its commanded hand path and its clock), so a test can play the
// gripper's reading back to it without physics: shut on nothing, or stopped by the object.
#include "scenarios/pick_expert.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "configs/robot_config.h"
#include "engine/object_catalog.h"
#include "scenarios/registry.h"

namespace tavis::scenarios {
namespace {

class PickExpertTest : public ::testing::Test {
 protected:
  // One env of `task` on GR1T2 at the reset of `episode`, its objects resting on the table.
  void ResetTask(const std::string& task, uint64_t episode) {
    scenario_ = &FindScenario(task);
    model_ = engine::WorldModel();
    model_.robot = configs::LoadRobotModel(configs::RobotConfigPath(TAVIS_CONFIG_DIR, "gr1t2"));
    scenario_->layout(model_);
    state_ = engine::BatchState();
    state_.Allocate(1, model_.robot.num_joints(), model_.num_objects());
    const std::vector<double> q = model_.robot.DefaultPositions();
    std::copy(q.begin(), q.end(), state_.q_row(0));
    state_.task_rng[0] = engine::RandomStream(0, engine::RandomStreamId::kTask, episode);
    scenario_->reset(model_, Split::kId, state_, 0);
    for (int object = 0; object < model_.num_objects(); ++object) {
      if (model_.objects[static_cast<std::size_t>(object)].motion == engine::ObjectMotion::kKinematic) continue;
      const double half_height = BoundingHalfSize(model_.objects[static_cast<std::size_t>(object)].shape).z();
      state_.object_pose_row(0, object)[2] = engine::kTableHeight + half_height;
    }
    expert_ = scenario_->make_expert(model_, 1);
    expert_->Reset(model_, state_, 0);
  }

  int Target() const { return state_.target(0); }

  // Steps the expert `ticks` control ticks. A closed gripper reads `held_gap` (the object's
  // width when it holds it, the shut gap when it closed on nothing); an open one, its open gap.
  // Returns the commanded action at each tick on which a gripper command turned to closed.
  std::vector<kinematics::Action> Run(int ticks, double held_gap) {
    std::vector<kinematics::Action> closings;
    kinematics::Action action{};
    std::array<bool, 2> closed{false, false};
    for (int tick = 0; tick < ticks; ++tick) {
      expert_->Act(model_, state_, 0, action);
      for (const kinematics::Side side : kinematics::kSides) {
        const int i = kinematics::Index(side);
        const bool now_closed = action[kinematics::action::kGripper[i]] > 0.0;
        if (now_closed && !closed[static_cast<std::size_t>(i)]) closings.push_back(action);
        closed[static_cast<std::size_t>(i)] = now_closed;
        state_.gripper_gap[static_cast<std::size_t>(i)] = now_closed ? held_gap : model_.robot.gripper.open_gap;
      }
      ++state_.control_step[0];
    }
    return closings;
  }

  // The commanded pads' centre (world) and hand orientation of `side` in an action.
  Vec3 CommandedPads(const kinematics::Action& action, kinematics::Side side, Mat3* R = nullptr) const {
    const int p = kinematics::action::kArmPosition[kinematics::Index(side)];
    const int r = kinematics::action::kArmQuaternion[kinematics::Index(side)];
    const Mat3 R_hand = Quat(action[r], action[r + 1], action[r + 2], action[r + 3]).normalized().toRotationMatrix();
    if (R) *R = R_hand;
    const Vec3 ik = model_.robot.CanonicalToBase(Vec3(action[p], action[p + 1], action[p + 2])) + model_.robot.root_world;
    return ik + R_hand * model_.robot.gripper.pad_center;
  }

  static kinematics::Side ClosingSide(const kinematics::Action& action) {
    return action[kinematics::action::kGripper[0]] > 0.0 ? kinematics::Side::kLeft : kinematics::Side::kRight;
  }

  const ScenarioDef* scenario_ = nullptr;
  engine::WorldModel model_;
  engine::BatchState state_;
  std::unique_ptr<Expert> expert_;
};

constexpr int kTwentySeconds = 1200;  // control ticks

TEST_F(PickExpertTest, RetriesWithAnotherHandOrientationWhenTheGripperClosesOnNothing) {
  ResetTask("clutter-pick-cube", 0);
  const std::vector<kinematics::Action> closings = Run(kTwentySeconds, model_.robot.gripper.closed_gap);
  // Three grasps, each with a hand orientation not tried before, then the expert gives up.
  ASSERT_EQ(closings.size(), 3u);
  std::vector<Mat3> orientations;
  for (const kinematics::Action& closing : closings) {
    Mat3 R;
    const Vec3 pads = CommandedPads(closing, ClosingSide(closing), &R);
    EXPECT_LT((pads - state_.ObjectPosition(0, Target())).norm(), 0.03) << "each grasp is at the cube";
    for (const Mat3& before : orientations) {
      EXPECT_GT(Eigen::AngleAxisd(before.transpose() * R).angle(), 0.1) << "a failed hand orientation was tried again";
    }
    orientations.push_back(R);
  }
  EXPECT_EQ(dynamic_cast<const PickExpert&>(*expert_).attempts(0), 3);
  EXPECT_EQ(dynamic_cast<const PickExpert&>(*expert_).phase(0), PickExpert::Phase::kGiveUp);
  EXPECT_TRUE(expert_->gave_up(0)) << "the episode driver ends the episode on it";
}

TEST_F(PickExpertTest, KeepsAndLiftsAGraspThatHoldsTheObject) {
  ResetTask("clutter-pick-cube", 0);
  const double cube_width = 0.055;
  const std::vector<kinematics::Action> closings = Run(kTwentySeconds, cube_width);
  ASSERT_EQ(closings.size(), 1u);
  kinematics::Action last{};
  expert_->Act(model_, state_, 0, last);
  const kinematics::Side side = ClosingSide(closings[0]);
  EXPECT_GT(CommandedPads(last, side).z() - CommandedPads(closings[0], side).z(), 0.15) << "the held cube is lifted";
  EXPECT_EQ(dynamic_cast<const PickExpert&>(*expert_).attempts(0), 1);
  EXPECT_FALSE(expert_->gave_up(0));
}

TEST_F(PickExpertTest, PadsOverlapALowCanInsideTheBox) {
  // A level hand reaching into the box, raised until its housing clears the table, would close
  // its pads above the 25 mm tuna can; the grasp must hold the can over most of its height.
  const int tuna = 2;
  ASSERT_EQ(engine::TavisHeadObjectNames()[tuna], "tuna_fish_can");
  int tuna_episodes = 0;
  for (uint64_t episode = 0; episode < 40; ++episode) {
    ResetTask("peeking-box", episode);
    if (Target() != tuna) continue;
    ++tuna_episodes;
    const std::vector<kinematics::Action> closings = Run(kTwentySeconds, 0.06);
    ASSERT_FALSE(closings.empty()) << "episode " << episode;
    Mat3 R;
    const Vec3 pads = CommandedPads(closings[0], ClosingSide(closings[0]), &R);
    const double pad_half_height = (R.transpose() * Vec3::UnitZ()).cwiseAbs().dot(0.5 * model_.robot.gripper.pad_size);
    const Vec3 can = state_.ObjectPosition(0, tuna);
    const double can_half_height = BoundingHalfSize(model_.objects[tuna].shape).z();
    const double overlap = std::min(can.z() + can_half_height, pads.z() + pad_half_height) -
                           std::max(can.z() - can_half_height, pads.z() - pad_half_height);
    EXPECT_GE(overlap, 0.6 * 2.0 * can_half_height) << "episode " << episode << ": pads at z " << pads.z();
  }
  EXPECT_GE(tuna_episodes, 4);
}

}  // namespace
}  // namespace tavis::scenarios
