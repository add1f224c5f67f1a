#include "bench/peer/expert_trajectories.h"

#include <algorithm>
#include <utility>

#include "batch/builtin_policies.h"
#include "batch/scene/scene_plan.h"
#include "batch/vec_env.h"

namespace tavis::peer {

ExpertTrajectories RecordExpertTrajectories(const std::string& config_dir, const std::string& task,
                                            const std::string& robot, int episodes, int ticks) {
  batch::scene::SceneSpec spec;
  spec.task = task;
  spec.robot = robot;
  spec.config_dir = config_dir;
  batch::scene::ScenePlan plan = batch::scene::PlanScene(spec);
  const scenarios::ScenarioDef& scenario = *plan.scenario;
  batch::VecEnv vec_env(std::move(plan.model), scenario, spec.split, episodes, spec.seed);
  batch::ExpertPolicy policy(scenario, vec_env.model(), episodes);

  std::vector<batch::EpisodeStart> starts;
  for (int e = 0; e < episodes; ++e) starts.push_back({e, e});
  vec_env.Reset(starts);
  const engine::BatchState& state = vec_env.state();
  std::vector<const char*> prompts(static_cast<std::size_t>(episodes));
  for (int e = 0; e < episodes; ++e) prompts[static_cast<std::size_t>(e)] = scenario.prompt(state, e);
  const batch::Observation observation{vec_env.model(), state, nullptr, prompts, nullptr};
  std::vector<uint8_t> all(static_cast<std::size_t>(episodes), 1);
  policy.Reset(observation, all);

  ExpertTrajectories out;
  out.model = vec_env.model();
  out.ticks = ticks;
  const int nj = state.num_joints;
  const int no = state.num_objects;
  out.episodes.resize(static_cast<std::size_t>(episodes));
  for (int e = 0; e < episodes; ++e) {
    EpisodeTrajectory& t = out.episodes[static_cast<std::size_t>(e)];
    t.q0.assign(state.q_row(e), state.q_row(e) + nj);
    t.object_pose0.assign(state.object_pose_row(e, 0), state.object_pose_row(e, 0) + no * engine::kObjectPoseSize);
    t.object_enabled.assign(state.object_enabled.begin() + static_cast<std::ptrdiff_t>(e) * no,
                            state.object_enabled.begin() + static_cast<std::ptrdiff_t>(e + 1) * no);
  }
  batch::ActionBatch actions(static_cast<std::size_t>(episodes));
  for (int tick = 0; tick < ticks; ++tick) {
    std::vector<uint8_t> acting(static_cast<std::size_t>(episodes));
    for (int e = 0; e < episodes; ++e) acting[static_cast<std::size_t>(e)] = state.running(e) ? 1 : 0;
    policy.Act(observation, acting, actions);
    vec_env.Step(actions);
    for (int e = 0; e < episodes; ++e) {
      EpisodeTrajectory& t = out.episodes[static_cast<std::size_t>(e)];
      // An ended episode is no longer stepped, so its row holds its last command.
      t.q_target.insert(t.q_target.end(), state.q_target_row(e), state.q_target_row(e) + nj);
      t.gripper_command.insert(t.gripper_command.end(), state.gripper_command_row(e), state.gripper_command_row(e) + 2);
      if (state.end[static_cast<std::size_t>(e)] == engine::EpisodeEnd::kSuccess) t.success = true;
    }
  }
  return out;
}

}  // namespace tavis::peer
