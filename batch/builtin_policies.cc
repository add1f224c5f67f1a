#include "batch/builtin_policies.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "batch/action_csv.h"
#include "kinematics/forward_kinematics.h"

namespace tavis::batch {
namespace {

class HoldPolicy : public PerEnvPolicy {
 public:
  explicit HoldPolicy(int num_envs) : reset_action_(num_envs) {}
  std::string name() const override { return "hold"; }
  int control_ticks_per_action() const override { return 3; }

 private:
  void ResetEnv(const Observation& observation, int env) override {
    const kinematics::RobotModel& robot = observation.model.robot;
    std::vector<RigidTransform> X_BL(robot.links.size());
    kinematics::ComputeLinkPoses(robot, observation.state.q_row(env), X_BL.data());
    kinematics::Action& action = reset_action_[env];
    action.fill(0.0);
    for (kinematics::Side side : kinematics::kSides) {
      const RigidTransform& X = X_BL[robot.arm(side).ik_link];
      const Vec3 p = robot.BaseToCanonical(X.translation());
      const Quat q(X.linear());
      const int i = kinematics::Index(side);
      for (int k = 0; k < 3; ++k) action[kinematics::action::kArmPosition[i] + k] = p[k];
      const double wxyz[4] = {q.w(), q.x(), q.y(), q.z()};
      for (int k = 0; k < 4; ++k) action[kinematics::action::kArmQuaternion[i] + k] = wxyz[k];
      action[kinematics::action::kGripper[i]] = -1.0;
    }
  }
  void ActEnv(const Observation&, int env, kinematics::Action& action) override { action = reset_action_[env]; }

  std::vector<kinematics::Action> reset_action_;
};

class ReplayPolicy : public PerEnvPolicy {
 public:
  explicit ReplayPolicy(const std::string& actions_file) : trajectory_(ReadActionCsv(actions_file)) {}
  std::string name() const override { return "replay"; }
  int control_ticks_per_action() const override { return kControlTicksPerRow; }

 private:
  void ResetEnv(const Observation&, int) override {}
  void ActEnv(const Observation& observation, int env, kinematics::Action& action) override {
    const int row = std::min(observation.state.control_step[env] / kControlTicksPerRow, trajectory_.num_steps - 1);
    std::copy_n(&trajectory_.values[static_cast<size_t>(row) * kinematics::action::kSize], kinematics::action::kSize,
                action.begin());
  }

  static constexpr int kControlTicksPerRow = 3;  // rows are 20 Hz policy steps
  ActionTrajectory trajectory_;
};

std::unique_ptr<scenarios::Expert> MakeExpert(const scenarios::ScenarioDef& scenario, const engine::WorldModel& model,
                                              int num_envs, scenarios::ExpertMode mode) {
  if (scenario.make_expert == nullptr) {
    throw std::invalid_argument("task '" + scenario.name + "' has no scripted expert yet");
  }
  return scenario.make_expert(model, num_envs, mode);
}

}  // namespace

ExpertPolicy::ExpertPolicy(const scenarios::ScenarioDef& scenario, const engine::WorldModel& model, int num_envs,
                           scenarios::ExpertMode mode)
    : expert_(MakeExpert(scenario, model, num_envs, mode)) {}

void ExpertPolicy::ResetEnv(const Observation& observation, int env) {
  expert_->Reset(observation.model, observation.state, env);
}

void ExpertPolicy::ActEnv(const Observation& observation, int env, kinematics::Action& action) {
  expert_->Act(observation.model, observation.state, env, action);
}

const char* BuiltinPolicyNames() { return "expert, hold, replay"; }

void CheckBuiltinPolicyName(const std::string& name) {
  if (name != "expert" && name != "hold" && name != "replay") {
    throw std::invalid_argument("unknown policy '" + name + "' (built in: " + BuiltinPolicyNames() + ")");
  }
}

std::unique_ptr<Policy> MakeBuiltinPolicy(const std::string& name, const scenarios::ScenarioDef& scenario,
                                          const engine::WorldModel& model, int num_envs,
                                          const std::string& actions_file, scenarios::ExpertMode expert_mode) {
  CheckBuiltinPolicyName(name);
  if (name == "expert") return std::make_unique<ExpertPolicy>(scenario, model, num_envs, expert_mode);
  if (name == "hold") return std::make_unique<HoldPolicy>(num_envs);
  if (actions_file.empty()) throw std::invalid_argument("policy 'replay' needs an actions file (--actions FILE.csv)");
  return std::make_unique<ReplayPolicy>(actions_file);
}

}  // namespace tavis::batch
