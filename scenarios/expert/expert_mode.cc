#include "scenarios/expert/expert_mode.h"

#include <stdexcept>

namespace tavis::scenarios::expert {

ExpertMode ParseExpertMode(const std::string& text) {
  if (text == "gaze-first") return ExpertMode::kGazeFirst;
  if (text == "head-still") return ExpertMode::kHeadStill;
  throw std::invalid_argument("unknown expert mode '" + text + "' (expected " + ExpertModeNames() + ")");
}

const char* ToString(ExpertMode mode) {
  switch (mode) {
    case ExpertMode::kGazeFirst: return "gaze-first";
    case ExpertMode::kHeadStill: return "head-still";
  }
  return "unknown";
}

const char* ExpertModeNames() { return "gaze-first, head-still"; }

}  // namespace tavis::scenarios::expert
