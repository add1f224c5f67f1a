// Test support: check_video.py (Debian's PyAV 10) run on one mp4: the stream's facts and LeRobot's
// seek-and-decode lookup of frames, each found frame read back as rgb24.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/batch/dataset/synthetic_frames.h"

namespace tavis::batch::dataset::testing {

struct FrameQuery {
  double from_timestamp = 0;  // the episode's start in the file, as the episodes table holds it
  int frame_index = 0;        // within the episode
};

struct PyAvReport {
  nlohmann::json stream;                        // check_video.py's report (its "lookups" included)
  std::vector<std::optional<RgbFrame>> frames;  // per query; empty when LeRobot's lookup finds none
};

// Runs check_video.py on `path`; the found frames pass through files in `scratch_dir`.
PyAvReport CheckVideoWithPyAv(const std::string& path, int fps, const std::vector<FrameQuery>& queries,
                              const std::string& scratch_dir);

}  // namespace tavis::batch::dataset::testing
