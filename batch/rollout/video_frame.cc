#include "batch/rollout/video_frame.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace tavis::batch::rollout {
namespace {

const int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr int kPad = 6;

// The caption's font scale for a frame `width` pixels wide: legible on a 320-pixel tile, growing
// with the frame.
double CaptionScale(int width) { return std::max(0.45, width / 1400.0); }

int CaptionThickness(double scale) { return std::max(1, static_cast<int>(std::lround(1.6 * scale))); }

int CaptionLineHeight(int width) {
  const double scale = CaptionScale(width);
  int baseline = 0;
  const cv::Size text = cv::getTextSize("Ag", kFont, scale, CaptionThickness(scale), &baseline);
  return text.height + baseline + kPad;
}

// The band's height: kCaptionLines lines, rounded up to an even number of rows.
int CaptionHeight(int width) {
  const int height = kCaptionLines * CaptionLineHeight(width) + kPad;
  return height + height % 2;
}

}  // namespace

std::pair<int, int> VideoFrameSize(int cameras, int tile_width, int tile_height) {
  // As render::MakeContactSheet lays them out: a near-square grid with 4-pixel margins.
  std::vector<uint8_t> pixel(static_cast<std::size_t>(tile_width) * static_cast<std::size_t>(tile_height) * 3);
  const std::vector<render::LabelledImage> views(static_cast<std::size_t>(cameras),
                                                 render::LabelledImage{"", tile_height, tile_width, pixel.data()});
  const render::RgbImage sheet = render::MakeContactSheet(views);
  return {sheet.width, sheet.height + CaptionHeight(sheet.width)};
}

render::RgbImage ComposeVideoFrame(const std::vector<render::LabelledImage>& views,
                                   const std::vector<std::string>& caption) {
  if (caption.size() > static_cast<std::size_t>(kCaptionLines)) {
    throw std::invalid_argument("a video frame's caption holds at most " + std::to_string(kCaptionLines) +
                                " lines, got " + std::to_string(caption.size()));
  }
  const render::RgbImage sheet = render::MakeContactSheet(views);
  const int band = CaptionHeight(sheet.width);
  render::RgbImage frame;
  frame.width = sheet.width;
  frame.height = sheet.height + band;
  frame.pixels.assign(static_cast<std::size_t>(frame.width) * static_cast<std::size_t>(frame.height) * 3, 0);
  std::memcpy(frame.pixels.data() + static_cast<std::size_t>(band) * static_cast<std::size_t>(frame.width) * 3,
              sheet.pixels.data(), sheet.pixels.size());
  cv::Mat canvas(frame.height, frame.width, CV_8UC3, frame.pixels.data());
  const double scale = CaptionScale(frame.width);
  const int line_height = CaptionLineHeight(frame.width);
  for (std::size_t line = 0; line < caption.size(); ++line) {
    int baseline = 0;
    const cv::Size text = cv::getTextSize(caption[line], kFont, scale, CaptionThickness(scale), &baseline);
    const int y = kPad + static_cast<int>(line) * line_height + text.height;
    cv::putText(canvas, caption[line], cv::Point(kPad, y), kFont, scale, cv::Scalar(255, 255, 255),
                CaptionThickness(scale), cv::LINE_AA);
  }
  return frame;
}

}  // namespace tavis::batch::rollout
