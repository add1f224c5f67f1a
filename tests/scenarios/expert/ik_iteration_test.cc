#include "scenarios/expert/ik_iteration.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "kinematics/forward_kinematics.h"
#include "tests/support/robot_loading.h"

namespace tavis::scenarios::expert {
namespace {

constexpr int kPlannerSteps = 150;  // arm_planner.cc's iterations per seed
constexpr double kPlannerStillStep = 1e-9;

bool SameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// The planner's situation: the arm started at a random configuration within its limits, toward
// a hand pose that some configuration reaches, moved by up to 15 cm (often out of reach), so that
// seeds converge, stall, and fall into cycles at joint limits.
struct Trial {
  std::vector<double> q_start;
  kinematics::PoseTarget target;
};

Trial RandomTrial(const kinematics::RobotModel& robot, kinematics::Side side, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto random_arm = [&](std::vector<double>& q) {
    for (const int j : robot.arm(side).joints) {
      const kinematics::Joint& joint = robot.joints[static_cast<std::size_t>(j)];
      q[static_cast<std::size_t>(j)] = joint.lower + unit(rng) * (joint.upper - joint.lower);
    }
  };
  Trial trial;
  trial.q_start = robot.DefaultPositions();
  std::vector<double> q_goal = trial.q_start;
  random_arm(trial.q_start);
  random_arm(q_goal);
  std::vector<RigidTransform> X_BL(robot.links.size());
  kinematics::ComputeLinkPoses(robot, q_goal.data(), X_BL.data());
  const RigidTransform& X_B_hand = X_BL[static_cast<std::size_t>(robot.arm(side).ik_link)];
  const Vec3 offset(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5);
  trial.target = {X_B_hand.translation() + 0.3 * unit(rng) * offset, Quat(X_B_hand.linear())};
  return trial;
}

class IkIterationTest : public ::testing::TestWithParam<std::string> {};

TEST_P(IkIterationTest, TheCycleShortcutEndsWhereEveryStepWould) {
  const kinematics::RobotModel robot = tavis::testing::LoadRobot(GetParam());
  std::mt19937 rng(20261126);
  int cycles = 0;
  int steps_saved = 0;
  for (int t = 0; t < 240; ++t) {
    const kinematics::Side side = kinematics::kSides[static_cast<std::size_t>(t % 2)];
    const Trial trial = RandomTrial(robot, side, rng);
    const std::vector<int> arm_links = kinematics::LinksMovedByArm(robot, side);
    std::vector<RigidTransform> X_BL_full(robot.links.size()), X_BL_short(robot.links.size());
    kinematics::ComputeLinkPoses(robot, trial.q_start.data(), X_BL_full.data());
    X_BL_short = X_BL_full;
    std::vector<double> q_full = trial.q_start, q_short = trial.q_start;
    const IkIteration full = IterateIk(robot, side, q_full, trial.target, arm_links, X_BL_full, kPlannerSteps,
                                       kPlannerStillStep, CycleShortcut::kOff);
    const IkIteration shortcut = IterateIk(robot, side, q_short, trial.target, arm_links, X_BL_short, kPlannerSteps,
                                           kPlannerStillStep, CycleShortcut::kOn);
    ASSERT_FALSE(full.cycle_found);
    ASSERT_TRUE(SameBits(q_full, q_short)) << "trial " << t;
    for (const int link : arm_links) {
      ASSERT_TRUE(X_BL_full[static_cast<std::size_t>(link)].matrix() ==
                  X_BL_short[static_cast<std::size_t>(link)].matrix())
          << "trial " << t << " link " << link;
    }
    if (shortcut.cycle_found) {
      ++cycles;
      steps_saved += full.steps - shortcut.steps;
    } else {
      EXPECT_EQ(shortcut.steps, full.steps) << "trial " << t;
    }
  }
  // The trials must fall into cycles for the comparison to mean something.
  EXPECT_GE(cycles, 5);
  EXPECT_GT(steps_saved, 5 * 50);
}

INSTANTIATE_TEST_SUITE_P(Robots, IkIterationTest, ::testing::Values("gr1t2", "reachy2"));

// The hand's own pose from the default configuration (where the null-space pull is zero): the
// first step barely moves the arm and the iteration stops there, with or without the shortcut.
TEST(IkIteration, StopsAtAFixedPointWithOrWithoutTheShortcut) {
  const kinematics::RobotModel robot = tavis::testing::LoadRobot("gr1t2");
  const kinematics::Side side = kinematics::Side::kLeft;
  const std::vector<int> arm_links = kinematics::LinksMovedByArm(robot, side);
  std::vector<double> q = robot.DefaultPositions();
  std::vector<RigidTransform> X_BL(robot.links.size());
  kinematics::ComputeLinkPoses(robot, q.data(), X_BL.data());
  const RigidTransform X_B_hand = X_BL[static_cast<std::size_t>(robot.arm(side).ik_link)];
  const kinematics::PoseTarget here{X_B_hand.translation(), Quat(X_B_hand.linear())};
  for (const CycleShortcut shortcut : {CycleShortcut::kOn, CycleShortcut::kOff}) {
    std::vector<double> q_run = q;
    const IkIteration run =
        IterateIk(robot, side, q_run, here, arm_links, X_BL, kPlannerSteps, kPlannerStillStep, shortcut);
    EXPECT_LT(run.steps, kPlannerSteps);
    EXPECT_FALSE(run.cycle_found);
    for (const int j : robot.arm(side).joints) {
      EXPECT_NEAR(q_run[static_cast<std::size_t>(j)], q[static_cast<std::size_t>(j)], 1e-6);
    }
  }
}

}  // namespace
}  // namespace tavis::scenarios::expert
