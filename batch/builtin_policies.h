// Policies built into the simulator: the task's scripted expert and a hold-still baseline.
#pragma once

#include <memory>
#include <string>

#include "batch/policy.h"
#include "scenarios/scenario.h"

namespace tavis::batch {

// Names accepted by MakeBuiltinPolicy, for --help texts and errors.
const char* BuiltinPolicyNames();

// "expert": the scenario's privileged scripted expert at the control rate.
// "hold": keeps the arms at their reset pose, head still, grippers open (a lower reference).
// Throws std::invalid_argument naming an unknown policy.
std::unique_ptr<Policy> MakeBuiltinPolicy(const std::string& name, const scenarios::ScenarioDef& scenario,
                                          const engine::WorldModel& model, int num_envs);

}  // namespace tavis::batch
