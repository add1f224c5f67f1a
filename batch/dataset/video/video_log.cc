#include "batch/dataset/video/video_log.h"

#include <cstdlib>

extern "C" {
#include <libavutil/log.h>
}

namespace tavis::batch::dataset::video {

void ShowOnlyVideoErrors() {
  av_log_set_level(AV_LOG_ERROR);
  setenv("SVT_LOG", "1", 0);  // SVT-AV1's own logger: errors only, unless the user chose a level
}

}  // namespace tavis::batch::dataset::video
