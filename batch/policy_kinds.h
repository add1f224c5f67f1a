// Every policy a cell can run, declared once: its name on the command line, in cell.json and in a
// sweep spec, and what kind it is. Code asks this table (IsPolicy) instead of comparing names.
#pragma once

#include <array>
#include <string>

namespace tavis::batch {

enum class PolicyKind { kExpert, kHold, kReplay, kOpenpi };

struct PolicyDecl {
  PolicyKind kind;
  const char* name;
  bool built_in;  // made by MakeBuiltinPolicy (builtin_policies.h); else served (remote/)
};

// In the order the help texts and errors list them: the built-in ones, then the served one.
inline constexpr std::array<PolicyDecl, 4> kPolicies = {{
    {PolicyKind::kExpert, "expert", true},
    {PolicyKind::kHold, "hold", true},
    {PolicyKind::kReplay, "replay", true},
    {PolicyKind::kOpenpi, "openpi", false},
}};

// The declaration of `name`, or null if no policy has that name.
const PolicyDecl* FindPolicy(const std::string& name);
// True if `name` is the policy of that kind.
bool IsPolicy(const std::string& name, PolicyKind kind);
// The name of a kind ("expert", ...).
const char* PolicyName(PolicyKind kind);
// The names of the built-in policies ("expert, hold, replay"), or of all ("..., openpi").
std::string PolicyNames(bool built_in_only);

}  // namespace tavis::batch
