// FFmpeg and SVT-AV1 print statistics and banners for every encoder they open and close (one per
// episode and camera): a recording run shows only their errors.
#pragma once

namespace tavis::batch::dataset::video {

void ShowOnlyVideoErrors();

}  // namespace tavis::batch::dataset::video
