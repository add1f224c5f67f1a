#include "batch/builtin_policies.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "batch/action_csv.h"
#include "kinematics/forward_kinematics.h"

namespace tavis::batch {
namespace {

class HoldPolicy : public PerEnvPolicy {
 public:
  explicit HoldPolicy(int num_envs) : reset_action_(num_envs) {}
  std::string name() const override { return PolicyName(PolicyKind::kHold); }
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

// Plays one CSV in every episode, or, given a folder (a served cell's DIR/actions), episode i's
// own DIR/episode_<i>.csv (or .csv.gz, as cells save them), read when the episode starts.
class ReplayPolicy : public PerEnvPolicy {
 public:
  ReplayPolicy(const std::string& actions, int num_envs)
      : folder_(std::filesystem::is_directory(actions) ? actions : "") {
    if (folder_.empty()) {
      shared_ = ReadActionCsv(actions);
    } else {
      per_env_.resize(static_cast<std::size_t>(num_envs));
    }
  }
  std::string name() const override { return PolicyName(PolicyKind::kReplay); }
  int control_ticks_per_action() const override { return kControlTicksPerRow; }

 private:
  void ResetEnv(const Observation& observation, int env) override {
    if (folder_.empty()) return;
    const int64_t episode = observation.state.episode[env];
    const std::filesystem::path path = FindEpisodeActions(folder_, episode);
    if (path.empty()) {
      throw std::runtime_error(
          "policy 'replay': " +
          (std::filesystem::path(folder_) / ("episode_" + std::to_string(episode) + ".csv")).string() +
          " does not exist, nor " + EpisodeActionsName(episode) + " (the folder has no actions for episode " +
          std::to_string(episode) + ")");
    }
    per_env_[static_cast<std::size_t>(env)] = ReadActionCsv(path);
  }
  void ActEnv(const Observation& observation, int env, kinematics::Action& action) override {
    const ActionTrajectory& trajectory = folder_.empty() ? shared_ : per_env_[static_cast<std::size_t>(env)];
    const int row = std::min(observation.state.control_step[env] / kControlTicksPerRow, trajectory.num_steps - 1);
    std::copy_n(&trajectory.values[static_cast<size_t>(row) * kinematics::action::kSize], kinematics::action::kSize,
                action.begin());
  }

  static constexpr int kControlTicksPerRow = 3;  // rows are 20 Hz policy steps
  std::string folder_;
  ActionTrajectory shared_;
  std::vector<ActionTrajectory> per_env_;  // (num_envs) with a folder: the running episode's
};

std::unique_ptr<scenarios::Expert> MakeExpert(const scenarios::ScenarioDef& scenario, const engine::WorldModel& model,
                                              int num_envs, scenarios::expert::ExpertMode mode) {
  if (scenario.make_expert == nullptr) {
    throw std::invalid_argument("task '" + scenario.name + "' has no scripted expert yet");
  }
  return scenario.make_expert(model, num_envs, mode);
}

}  // namespace

ExpertPolicy::ExpertPolicy(const scenarios::ScenarioDef& scenario, const engine::WorldModel& model, int num_envs,
                           scenarios::expert::ExpertMode mode, int decide_every)
    : expert_(MakeExpert(scenario, model, num_envs, mode)),
      decide_every_(decide_every),
      held_(static_cast<std::size_t>(num_envs)) {
  if (decide_every < 1)
    throw std::invalid_argument("the expert must decide every >= 1 control ticks, got " + std::to_string(decide_every));
}

void ExpertPolicy::ResetEnv(const Observation& observation, int env) {
  expert_->Reset(observation.model, observation.state, env);
}

void ExpertPolicy::ActEnv(const Observation& observation, int env, kinematics::Action& action) {
  expert_->Act(observation.model, observation.state, env, action);
  if (decide_every_ == 1) return;
  kinematics::Action& held = held_[static_cast<std::size_t>(env)];
  if (observation.state.control_step[env] % decide_every_ == 0) held = action;
  action = held;
}

const char* BuiltinPolicyNames() {
  static const std::string names = PolicyNames(/*built_in_only=*/true);
  return names.c_str();
}

void CheckBuiltinPolicyName(const std::string& name) {
  const PolicyDecl* policy = FindPolicy(name);
  if (policy == nullptr || !policy->built_in) {
    throw std::invalid_argument("unknown policy '" + name + "' (built in: " + BuiltinPolicyNames() + ")");
  }
}

std::unique_ptr<Policy> MakeBuiltinPolicy(const std::string& name, const scenarios::ScenarioDef& scenario,
                                          const engine::WorldModel& model, int num_envs,
                                          const std::string& actions_file, scenarios::expert::ExpertMode expert_mode) {
  CheckBuiltinPolicyName(name);
  if (IsPolicy(name, PolicyKind::kExpert))
    return std::make_unique<ExpertPolicy>(scenario, model, num_envs, expert_mode);
  if (IsPolicy(name, PolicyKind::kHold)) return std::make_unique<HoldPolicy>(num_envs);
  if (actions_file.empty()) {
    throw std::invalid_argument("policy 'replay' needs actions_file: a CSV, or a folder of episode_<i>.csv");
  }
  return std::make_unique<ReplayPolicy>(actions_file, num_envs);
}

}  // namespace tavis::batch
