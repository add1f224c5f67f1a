#include "scenarios/split.h"

#include <stdexcept>

namespace tavis::scenarios {

Split ParseSplit(const std::string& text) {
  if (text == "id") return Split::kId;
  if (text == "ood-spatial" || text == "ood_spatial") return Split::kOodSpatial;
  if (text == "ood-init-pose" || text == "ood_init_pose") return Split::kOodInitPose;
  throw std::invalid_argument("unknown split '" + text + "' (expected id, ood-spatial or ood-init-pose)");
}

const char* ToString(Split split) {
  switch (split) {
    case Split::kId: return "id";
    case Split::kOodSpatial: return "ood-spatial";
    case Split::kOodInitPose: return "ood-init-pose";
  }
  return "unknown";
}

}  // namespace tavis::scenarios
