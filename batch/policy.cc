#include "batch/policy.h"

#include <tbb/parallel_for.h>

namespace tavis::batch {

void PerEnvPolicy::Reset(const Observation& observation, const std::vector<uint8_t>& started) {
  tbb::parallel_for(0, static_cast<int>(started.size()), [&](int env) {
    if (started[env]) ResetEnv(observation, env);
  });
}

void PerEnvPolicy::Act(const Observation& observation, const std::vector<uint8_t>& acting, ActionBatch& actions) {
  tbb::parallel_for(0, static_cast<int>(acting.size()), [&](int env) {
    if (acting[env]) ActEnv(observation, env, actions[env]);
  });
}

}  // namespace tavis::batch
