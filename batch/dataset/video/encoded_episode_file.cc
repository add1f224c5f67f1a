#include "batch/dataset/video/encoded_episode_file.h"

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

extern "C" {
#include <libavcodec/avcodec.h>
}

#include "batch/dataset/video/encoder_context.h"
#include "batch/dataset/video/ffmpeg_error.h"

namespace tavis::batch::dataset::video {
namespace {

constexpr char kMagic[8] = {'T', 'A', 'V', 'I', 'S', 'P', 'K', '1'};

template <typename T>
void Put(std::ofstream& out, T value) {
  unsigned char bytes[sizeof(T)];
  for (std::size_t i = 0; i < sizeof(T); ++i)
    bytes[i] = static_cast<unsigned char>(static_cast<uint64_t>(value) >> (8 * i));
  out.write(reinterpret_cast<const char*>(bytes), sizeof(T));
}

template <typename T>
T Get(std::ifstream& in, const std::string& path) {
  unsigned char bytes[sizeof(T)];
  if (!in.read(reinterpret_cast<char*>(bytes), sizeof(T)))
    throw std::runtime_error(path + ": truncated encoded episode");
  uint64_t value = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) value |= static_cast<uint64_t>(bytes[i]) << (8 * i);
  return static_cast<T>(value);
}

// What EpisodeEncoder gives episodes of `settings`: an encoder's parameters, taken as it opens.
// The encoder then encodes one frame before it is freed: SVT-AV1 1.4 hangs freeing an encoder
// that never saw a frame.
std::shared_ptr<const StreamParameters> ParametersFor(const VideoSettings& settings, const std::string& path) {
  const internal::CodecContextPtr encoder = internal::OpenEncoder(settings, path);
  std::shared_ptr<const StreamParameters> parameters = internal::ParametersOf(*encoder, path);
  AVFrame* frame = av_frame_alloc();
  AVPacket* packet = av_packet_alloc();
  if (frame == nullptr || packet == nullptr) throw std::runtime_error("video " + path + ": out of memory");
  frame->format = AV_PIX_FMT_YUV420P;
  frame->width = settings.width;
  frame->height = settings.height;
  int result = av_frame_get_buffer(frame, 0);
  if (result >= 0) {
    for (int plane = 0; plane < 3; ++plane)
      std::memset(frame->data[plane], 128,
                  static_cast<std::size_t>(frame->linesize[plane]) *
                      static_cast<std::size_t>(plane == 0 ? settings.height : settings.height / 2));
    frame->pts = 0;
    result = avcodec_send_frame(encoder.get(), frame);
  }
  if (result >= 0) result = avcodec_send_frame(encoder.get(), nullptr);
  while (result >= 0) {
    result = avcodec_receive_packet(encoder.get(), packet);
    av_packet_unref(packet);
  }
  av_packet_free(&packet);
  av_frame_free(&frame);
  if (result != AVERROR_EOF) internal::ThrowFfmpegError(path, "opening a reference encoder", result);
  return parameters;
}

}  // namespace

void SaveEncodedEpisode(const EncodedEpisode& episode, const std::string& path) {
  const std::string partial = path + ".partial";
  {
    std::ofstream out(partial, std::ios::binary);
    if (!out) throw std::runtime_error("cannot write " + partial + ": " + std::strerror(errno));
    out.write(kMagic, sizeof kMagic);
    Put<int64_t>(out, episode.frames);
    Put<uint64_t>(out, episode.packets.size());
    for (const EncodedPacket& packet : episode.packets) {
      Put<int64_t>(out, packet.pts);
      Put<int64_t>(out, packet.dts);
      Put<uint8_t>(out, packet.key ? 1 : 0);
      Put<uint32_t>(out, static_cast<uint32_t>(packet.data.size()));
      out.write(reinterpret_cast<const char*>(packet.data.data()), static_cast<std::streamsize>(packet.data.size()));
    }
    if (!out.flush()) throw std::runtime_error("cannot write " + partial + ": " + std::strerror(errno));
  }
  std::filesystem::rename(partial, path);
}

EncodedEpisode LoadEncodedEpisode(const std::string& path, const VideoSettings& settings) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  const uintmax_t size = std::filesystem::file_size(path);
  char magic[sizeof kMagic];
  if (!in.read(magic, sizeof magic) || std::memcmp(magic, kMagic, sizeof kMagic) != 0) {
    throw std::runtime_error(path + ": not an encoded episode (bad magic)");
  }
  EncodedEpisode episode;
  episode.frames = Get<int64_t>(in, path);
  const uint64_t packets = Get<uint64_t>(in, path);
  if (packets > size)
    throw std::runtime_error(path + ": claims " + std::to_string(packets) + " packets in " + std::to_string(size) +
                             " bytes");
  for (uint64_t i = 0; i < packets; ++i) {
    EncodedPacket packet;
    packet.pts = Get<int64_t>(in, path);
    packet.dts = Get<int64_t>(in, path);
    packet.key = Get<uint8_t>(in, path) != 0;
    const uint32_t bytes = Get<uint32_t>(in, path);
    if (bytes > size)
      throw std::runtime_error(path + ": a packet of " + std::to_string(bytes) + " bytes in a file of " +
                               std::to_string(size));
    packet.data.resize(bytes);
    if (!in.read(reinterpret_cast<char*>(packet.data.data()), bytes))
      throw std::runtime_error(path + ": truncated encoded episode");
    episode.packets.push_back(std::move(packet));
  }
  episode.parameters = ParametersFor(settings, path);
  return episode;
}

}  // namespace tavis::batch::dataset::video
