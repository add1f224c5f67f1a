#include "batch/policy.h"

#include <tbb/parallel_for.h>

#include "kinematics/cpu_clock.h"

namespace tavis::batch {

template <typename Body>
void PerEnvPolicy::Timed(int env, Body&& body) {
  if (!env_timing_) {
    body();
    return;
  }
  const int64_t start = kinematics::ThreadCpuNanoseconds();
  body();
  env_nanoseconds_[env] += kinematics::ThreadCpuNanoseconds() - start;
}

void PerEnvPolicy::Reset(const Observation& observation, const std::vector<uint8_t>& started) {
  tbb::parallel_for(0, static_cast<int>(started.size()), [&](int env) {
    if (started[env]) ResetOne(observation, env);
  });
}

void PerEnvPolicy::Act(const Observation& observation, const std::vector<uint8_t>& acting, ActionBatch& actions) {
  tbb::parallel_for(0, static_cast<int>(acting.size()), [&](int env) {
    if (acting[env]) ActOne(observation, env, actions[env]);
  });
}

void PerEnvPolicy::ResetOne(const Observation& observation, int env) {
  Timed(env, [&] { ResetEnv(observation, env); });
}

void PerEnvPolicy::ActOne(const Observation& observation, int env, kinematics::Action& action) {
  Timed(env, [&] { ActEnv(observation, env, action); });
}

void PerEnvPolicy::EnableEnvTiming(bool enabled, int num_envs) {
  env_timing_ = enabled;
  env_nanoseconds_.assign(enabled ? static_cast<std::size_t>(num_envs) : 0, 0);
}

double PerEnvPolicy::TakeEnvSeconds(int env) {
  if (static_cast<size_t>(env) >= env_nanoseconds_.size()) return 0.0;
  const double seconds = 1e-9 * static_cast<double>(env_nanoseconds_[env]);
  env_nanoseconds_[env] = 0;
  return seconds;
}

}  // namespace tavis::batch
