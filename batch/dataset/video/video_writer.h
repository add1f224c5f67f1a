// Mp4VideoWriter: one camera stream as one mp4 file holding one video stream.
//
// Contract (what LeRobot's readers rely on, lerobot-v3-format.md section 5):
// - RGB24 frames in (height x width x 3 uint8, row-major), yuv420p out;
// - constant frame rate: frame k (counted over the whole file) has pts exactly k / fps, the first
//   frame pts 0, and every packet, the last included, lasts one frame, so the probed stream
//   duration is exactly frames / fps;
// - a keyframe at least every `gop` frames and no B-frames; each episode (BeginEpisode()) is
//   encoded by a fresh encoder, as LeRobot encodes each episode into its own file, so episodes
//   laid back to back each start on a keyframe whatever their length (SVT-AV1 1.4 ignores
//   forced keyframes, so forcing one would not do);
// - moov before mdat (movflags=+faststart);
// - deterministic: the same settings and frames give byte-identical files (the encoder runs on
//   one thread; run several writers in parallel for throughput: distinct writers may be used
//   from distinct threads, one writer from one thread at a time);
// - the file is written as `path + ".partial"` and renamed to `path` by Close(); a writer
//   destroyed without Close() (an interrupted run) removes the partial file, so `path` never
//   holds a truncated mp4.
// Errors throw std::invalid_argument (bad settings, checked before any file is created) or
// std::runtime_error naming the file and FFmpeg's message (unwritable path, encoder missing,
// wrong frame size, disk full). After an error the writer is unusable.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "batch/dataset/video/episode_encoder.h"
#include "batch/dataset/video/video_settings.h"

namespace tavis::batch::dataset::video {

class Mp4VideoWriter {
 public:
  Mp4VideoWriter(std::string path, VideoSettings settings);
  ~Mp4VideoWriter();
  Mp4VideoWriter(Mp4VideoWriter&&) noexcept;
  Mp4VideoWriter& operator=(Mp4VideoWriter&&) noexcept;

  // Appends an episode encoded elsewhere (EpisodeEncoder with this writer's settings): its
  // packets follow the file's frames, with pts continuing from frames_written(). Throws
  // std::invalid_argument when its stream header differs from the file's (other settings).
  void AppendEpisode(const EncodedEpisode& episode);

  // The next frame starts an episode: it is encoded as a keyframe.
  void BeginEpisode();

  // Encodes one frame (into the current episode, appended at the next BeginEpisode or Close);
  // `rgb_size` must be width * height * 3.
  void WriteFrame(const std::uint8_t* rgb, std::size_t rgb_size);

  // Flushes the encoder, writes the index and renames the partial file to path(). Idempotent.
  void Close();

  std::int64_t frames_written() const;
  // Bytes of the file so far (with the current episode's encoded frames); Close() adds the index, about
  // a dozen bytes per frame. For rolling over to a new file at a size limit.
  std::int64_t bytes_written() const;
  const std::string& path() const;
  const VideoSettings& settings() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tavis::batch::dataset::video
