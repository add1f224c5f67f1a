// EpisodeEncoder: one camera's frames of one episode encoded into packets held in memory, so a
// recording can keep an episode until it knows whether the episode is kept (a dataset stores only
// successful episodes) and then append it to the camera's mp4 (Mp4VideoWriter::AppendEpisode).
// Each episode gets a fresh encoder, as LeRobot encodes each episode on its own: its first frame
// is a keyframe for any codec (SVT-AV1 1.4 ignores forced keyframes) and no episode's bytes depend
// on another's. Deterministic (one encoder thread; see video_writer.h), RGB24 in, yuv420p out.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "batch/dataset/video/video_settings.h"

namespace tavis::batch::dataset::video {

struct EncodedPacket {
  std::vector<std::uint8_t> data;
  std::int64_t pts = 0;  // in frames from the episode's first frame
  std::int64_t dts = 0;
  bool key = false;
};

// What a muxer needs to describe the stream (codec, size, headers); opaque outside tavis_video.
struct StreamParameters;

struct EncodedEpisode {
  std::vector<EncodedPacket> packets;  // in decoding order
  std::int64_t frames = 0;
  std::shared_ptr<const StreamParameters> parameters;  // equal headers for equal settings

  std::int64_t bytes() const;
};

class EpisodeEncoder {
 public:
  // Validates the settings (std::invalid_argument naming `name`, e.g. the camera) and opens an
  // encoder; std::runtime_error naming `name` and FFmpeg's message when it cannot.
  EpisodeEncoder(VideoSettings settings, std::string name);
  ~EpisodeEncoder();
  EpisodeEncoder(EpisodeEncoder&&) noexcept;
  EpisodeEncoder& operator=(EpisodeEncoder&&) noexcept;

  // Encodes one frame; `rgb_size` must be width * height * 3.
  void WriteFrame(const std::uint8_t* rgb, std::size_t rgb_size);
  // Flushes the encoder and hands over the episode; the encoder is then spent.
  EncodedEpisode Finish();

  std::int64_t frames() const;
  std::int64_t bytes() const;  // of the packets encoded so far
  const VideoSettings& settings() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tavis::batch::dataset::video
