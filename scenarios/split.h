// Evaluation splits (reference 3, 7.3). New axes are new entries, not booleans.
#pragma once

#include <string>

namespace tavis::scenarios {

enum class Split { kId, kOodSpatial, kOodInitPose };
constexpr Split kAllSplits[] = {Split::kId, Split::kOodSpatial, Split::kOodInitPose};

// Accepts "id", "ood-spatial", "ood-init-pose" (and the reference's underscore spellings);
// throws std::invalid_argument naming the value and the accepted ones.
Split ParseSplit(const std::string& text);
const char* ToString(Split split);

}  // namespace tavis::scenarios
