// A test policy that does nothing: it answers the whole batch (not a PerEnvPolicy) and leaves the
// actions as they are. Tests derive from it to give a policy one behaviour (faults, giving up) or
// use it where only the kind of policy matters (a profile's accounting).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "batch/policy.h"

namespace tavis::testing {

class IdlePolicy : public batch::Policy {
 public:
  explicit IdlePolicy(int control_ticks_per_action = 1) : control_ticks_per_action_(control_ticks_per_action) {}
  std::string name() const override { return "idle"; }
  int control_ticks_per_action() const override { return control_ticks_per_action_; }
  void Reset(const batch::Observation&, const std::vector<uint8_t>&) override {}
  void Act(const batch::Observation&, const std::vector<uint8_t>&, batch::ActionBatch&) override {}

 private:
  int control_ticks_per_action_;
};

}  // namespace tavis::testing
