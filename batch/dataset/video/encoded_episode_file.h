// An encoded episode saved as it came out of the encoder, to be appended to an mp4 later without
// decoding: a resumed recording takes up the episodes it had kept (episode_spool.h). The file is
// ours: "TAVISPK1", the frame count and packet count, then per packet pts, dts, key flag, size and
// bytes, all little-endian. Going through mp4 instead would hand the packets back in another
// framing (H.264's avcC instead of the encoder's Annex B) than freshly encoded episodes have.
#pragma once

#include <string>

#include "batch/dataset/video/episode_encoder.h"
#include "batch/dataset/video/video_settings.h"

namespace tavis::batch::dataset::video {

// Written to PATH.partial, then renamed. Throws std::runtime_error naming the file on failure.
void SaveEncodedEpisode(const EncodedEpisode& episode, const std::string& path);

// The episode saved at `path`, encoded with `settings` (which give its stream parameters).
// Throws std::runtime_error naming the file when it is missing, truncated or not such a file.
EncodedEpisode LoadEncodedEpisode(const std::string& path, const VideoSettings& settings);

}  // namespace tavis::batch::dataset::video
