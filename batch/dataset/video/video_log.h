// FFmpeg and SVT-AV1 print statistics and banners for every encoder they open and close (one per
// episode and camera): a recording run shows only their errors.
#pragma once

namespace tavis::dataset {

void ShowOnlyVideoErrors();

}  // namespace tavis::dataset
