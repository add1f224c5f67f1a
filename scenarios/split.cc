#include "scenarios/split.h"

#include <stdexcept>

#include "kinematics/enum_names.h"

namespace tavis::scenarios {

namespace {

constexpr kinematics::EnumName<Split> kSplitNames[] = {
    {Split::kId, "id"}, {Split::kOodSpatial, "ood-spatial"}, {Split::kOodInitPose, "ood-init-pose"}};
// The reference's spellings, read but never written.
constexpr kinematics::EnumName<Split> kReferenceSplitNames[] = {{Split::kOodSpatial, "ood_spatial"},
                                                                {Split::kOodInitPose, "ood_init_pose"}};

}  // namespace

Split ParseSplit(const std::string& text) {
  if (const auto* split = kinematics::FindNamed(kSplitNames, text)) return split->value;
  if (const auto* split = kinematics::FindNamed(kReferenceSplitNames, text)) return split->value;
  throw std::invalid_argument("unknown split '" + text + "' (expected id, ood-spatial or ood-init-pose)");
}

const char* ToString(Split split) { return kinematics::NameOf(kSplitNames, split, "unknown"); }

}  // namespace tavis::scenarios
