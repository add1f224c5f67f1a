#include "engine/batch_state.h"

namespace tavis::engine {

const char* ToString(EpisodeEnd end) {
  switch (end) {
    case EpisodeEnd::kRunning: return "running";
    case EpisodeEnd::kSuccess: return "success";
    case EpisodeEnd::kTimeOut: return "time_out";
    case EpisodeEnd::kPhysicsBlowUp: return "physics_blow_up";
    case EpisodeEnd::kInvalidAction: return "invalid_action";
    case EpisodeEnd::kStopped: return "stopped";
    case EpisodeEnd::kGaveUp: return "gave_up";
  }
  return "unknown";
}

bool ParseEpisodeEnd(const std::string& text, EpisodeEnd* end) {
  for (EpisodeEnd candidate :
       {EpisodeEnd::kRunning, EpisodeEnd::kSuccess, EpisodeEnd::kTimeOut, EpisodeEnd::kPhysicsBlowUp,
        EpisodeEnd::kInvalidAction, EpisodeEnd::kStopped, EpisodeEnd::kGaveUp}) {
    if (text == ToString(candidate)) {
      *end = candidate;
      return true;
    }
  }
  return false;
}

void BatchState::Allocate(int envs, int joints, int objects) {
  num_envs = envs;
  num_joints = joints;
  num_objects = objects;
  const size_t n = static_cast<size_t>(envs);
  q.assign(n * joints, 0.0);
  q_target.assign(n * joints, 0.0);
  gripper_command.assign(n * 2, -1.0);
  gripper_gap.assign(n * 2, 0.0);
  object_pose.assign(n * objects * kObjectPoseSize, 0.0);
  object_velocity.assign(n * objects * kObjectVelocitySize, 0.0);
  object_enabled.assign(n * objects, 0);
  object_rgb.assign(n * objects * 3, -1.0f);
  task.assign(n, TaskVars());
  task_state.assign(n, TaskStateBlock());
  control_step.assign(n, 0);
  policy_start_tick.assign(n, 0);
  episode.assign(n, -1);
  end.assign(n, EpisodeEnd::kRunning);
  invalid_action.assign(n, InvalidAction());
  images_current.assign(n, 0);
  task_rng.assign(n, RandomStream());
}

}  // namespace tavis::engine
