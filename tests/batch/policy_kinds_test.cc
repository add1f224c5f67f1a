#include "batch/policy_kinds.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "batch/builtin_policies.h"
#include "batch/cell/evaluation_cell.h"

namespace tavis::batch {
namespace {

TEST(PolicyKinds, EachNameFindsItsKindAndBack) {
  for (const PolicyDecl& policy : kPolicies) {
    const PolicyDecl* found = FindPolicy(policy.name);
    ASSERT_NE(found, nullptr) << policy.name;
    EXPECT_EQ(found->kind, policy.kind);
    EXPECT_EQ(std::string(PolicyName(policy.kind)), policy.name);
    EXPECT_TRUE(IsPolicy(policy.name, policy.kind));
  }
  EXPECT_FALSE(IsPolicy("expert", PolicyKind::kHold));
}

TEST(PolicyKinds, UnknownNamesAreNoPolicy) {
  EXPECT_EQ(FindPolicy("Expert"), nullptr);
  EXPECT_EQ(FindPolicy(""), nullptr);
  EXPECT_FALSE(IsPolicy("openpi ", PolicyKind::kOpenpi));
}

// The lists the help texts and errors print, as they were written before the table.
TEST(PolicyKinds, NameListsKeepTheirWording) {
  EXPECT_EQ(std::string(BuiltinPolicyNames()), "expert, hold, replay");
  EXPECT_EQ(cell::CellPolicyNames(), "expert, hold, replay, openpi");
  EXPECT_NO_THROW(CheckBuiltinPolicyName("replay"));
  EXPECT_THROW(CheckBuiltinPolicyName("openpi"), std::invalid_argument);  // served, not built in
  EXPECT_THROW(CheckBuiltinPolicyName("random"), std::invalid_argument);
}

}  // namespace
}  // namespace tavis::batch
