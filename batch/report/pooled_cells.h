// A label's cells pooled by setting: the episodes of every cell of one task, robot, split and
// camera (several seeds), in the order the settings first appear. The stage funnel and the
// failure events sections are computed per pooled setting.
#pragma once

#include <string>
#include <vector>

#include "batch/camera_protocol.h"
#include "batch/report/sweep_summary.h"

namespace tavis::batch::report {

struct PooledCell {
  std::string task;
  std::string robot;
  std::string split;
  CameraProtocol camera = CameraProtocol::kHead;
  std::vector<cell::EpisodeRecord> episodes;
};

std::vector<PooledCell> PoolBySetting(const std::vector<CellEpisodes>& cells);

}  // namespace tavis::batch::report
