#include "batch/episode_slots.h"

namespace tavis::batch {

EpisodeSlots::EpisodeSlots(VecEnv& vec_env)
    : vec_env_(vec_env),
      proprioception_(vec_env.model().robot, vec_env.num_envs()),
      prompts_(static_cast<std::size_t>(vec_env.num_envs()), nullptr),
      told_ended_(static_cast<std::size_t>(vec_env.num_envs()), 0) {}

void EpisodeSlots::SetCameraProtocol(CameraProtocol protocol) {
  protocol_ = protocol;
  proprioception_.SetCameraProtocol(protocol);
}

Observation EpisodeSlots::observation() const {
  return Observation{vec_env_.model(), vec_env_.state(), vec_env_.images(), prompts_, &proprioception_};
}

void EpisodeSlots::EpisodeReset(int slot) {
  prompts_[static_cast<std::size_t>(slot)] = vec_env_.prompt(slot);
  told_ended_[static_cast<std::size_t>(slot)] = 0;
}

bool EpisodeSlots::StopIfSinksAreDone(int slot) {
  bool done = false;
  for (const EpisodeSink* sink : sinks_) done = done || sink->EpisodeComplete(vec_env_, slot);
  if (done) vec_env_.EndEarly(slot, engine::EpisodeEnd::kStopped);
  return done;
}

void EpisodeSlots::ActionChosen(int slot, kinematics::Action& action) {
  ApplyProtocol(action);
  TellSinks(slot, [&](EpisodeSink& sink) { sink.ActionChosen(vec_env_, slot, action); });
}

void EpisodeSlots::EndIfGaveUp(const Policy& policy, int slot) {
  if (vec_env_.state().running(slot) && policy.GaveUp(slot)) vec_env_.EndEarly(slot, engine::EpisodeEnd::kGaveUp);
}

void EpisodeSlots::TellEnded(int slot) {
  if (observer_ != nullptr) observer_->EpisodeEnding(slot);
  for (EpisodeSink* sink : sinks_) sink->EpisodeEnded(vec_env_, slot);
  if (observer_ != nullptr) observer_->EpisodeEnded(slot);
  told_ended_[static_cast<std::size_t>(slot)] = 1;
}

void EpisodeSlots::Release(int slot) {
  vec_env_.Release(slot);
  prompts_[static_cast<std::size_t>(slot)] = nullptr;
}

}  // namespace tavis::batch
