#include "batch/dataset/video/encoder_options.h"

namespace tavis::batch::dataset::video::internal {

EncoderChoice ChooseEncoder(const VideoSettings& settings) {
  if (settings.codec == VideoCodec::kAv1) {
    const int crf = settings.crf >= 0 ? settings.crf : 30;
    // lp=1: one logical processor, so the output cannot depend on the machine's core count.
    return {"libsvtav1",
            {{"preset", std::to_string(settings.av1_preset)}, {"crf", std::to_string(crf)}, {"svtav1-params", "lp=1"}}};
  }
  const int crf = settings.crf >= 0 ? settings.crf : 23;
  return {"libx264", {{"preset", settings.h264_preset}, {"crf", std::to_string(crf)}}};
}

}  // namespace tavis::batch::dataset::video::internal
