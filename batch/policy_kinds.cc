#include "batch/policy_kinds.h"

namespace tavis::batch {

const PolicyDecl* FindPolicy(const std::string& name) {
  for (const PolicyDecl& policy : kPolicies) {
    if (name == policy.name) return &policy;
  }
  return nullptr;
}

bool IsPolicy(const std::string& name, PolicyKind kind) {
  const PolicyDecl* policy = FindPolicy(name);
  return policy != nullptr && policy->kind == kind;
}

const char* PolicyName(PolicyKind kind) {
  for (const PolicyDecl& policy : kPolicies) {
    if (policy.kind == kind) return policy.name;
  }
  return "";
}

std::string PolicyNames(bool built_in_only) {
  std::string names;
  for (const PolicyDecl& policy : kPolicies) {
    if (built_in_only && !policy.built_in) continue;
    names += (names.empty() ? "" : ", ") + std::string(policy.name);
  }
  return names;
}

}  // namespace tavis::batch
