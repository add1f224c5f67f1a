#include "scenarios/tabletop.h"

namespace tavis::scenarios {

const char* TargetPrompt(const TargetPrompts& prompts, const engine::BatchState& state, int env) {
  const engine::TaskVars& vars = state.task[env];
  TAVIS_INVARIANT(vars.prompt_variant >= 0 && vars.prompt_variant < static_cast<int>(prompts[0].size()),
                  "the task's reset drew one of the prompt's phrasings");
  return prompts[static_cast<std::size_t>(state.target(env))][static_cast<std::size_t>(vars.prompt_variant)];
}

}  // namespace tavis::scenarios
