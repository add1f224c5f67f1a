// Internal to tavis_video: which FFmpeg encoder a VideoSettings selects and the private options
// it gets. SVT-AV1 gets one logical processor (libx264's threads are pinned by the writer's
// thread_count 1), so the same frames always give the same bytes; callers parallelise across
// streams instead.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "batch/dataset/video/video_settings.h"

namespace tavis::batch::dataset::video::internal {

struct EncoderChoice {
  std::string encoder_name;                                          // e.g. "libx264", "libsvtav1"
  std::vector<std::pair<std::string, std::string>> private_options;  // av_opt_set on priv_data
};

EncoderChoice ChooseEncoder(const VideoSettings& settings);

}  // namespace tavis::batch::dataset::video::internal
