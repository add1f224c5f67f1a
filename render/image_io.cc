#include "render/image_io.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace tavis::render {
namespace {

constexpr int kSheetMargin = 4;
const cv::Scalar kSheetBackground(24, 24, 24);

void RequireImage(const char* what, int height, int width, const uint8_t* rgb) {
  if (height <= 0 || width <= 0 || rgb == nullptr) {
    throw std::invalid_argument(std::string(what) + ": invalid image " + std::to_string(height) + "x" +
                                std::to_string(width) + (rgb == nullptr ? " with no pixels" : ""));
  }
}

// A view of caller-owned RGB pixels as an OpenCV matrix (no copy; OpenCV does not modify it).
cv::Mat RgbView(int height, int width, const uint8_t* rgb) {
  return cv::Mat(height, width, CV_8UC3, const_cast<uint8_t*>(rgb));  // NOLINT: read-only use
}

// Label in white on a dark box so it reads on any image.
void DrawLabel(cv::Mat* cell, const std::string& label) {
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  const double scale = std::max(0.4, cell->cols / 900.0);
  const int thickness = std::max(1, static_cast<int>(std::lround(2.0 * scale)));
  int baseline = 0;
  const cv::Size text = cv::getTextSize(label, font, scale, thickness, &baseline);
  const int pad = 4;
  cv::rectangle(*cell, cv::Rect(0, 0, text.width + 2 * pad, text.height + baseline + 2 * pad), cv::Scalar(0, 0, 0),
                cv::FILLED);
  cv::putText(*cell, label, cv::Point(pad, pad + text.height), font, scale, cv::Scalar(255, 255, 255), thickness,
              cv::LINE_AA);
}

}  // namespace

void WritePng(const std::string& path, int height, int width, const uint8_t* rgb) {
  RequireImage(("WritePng '" + path + "'").c_str(), height, width, rgb);
  cv::Mat bgr;
  cv::cvtColor(RgbView(height, width, rgb), bgr, cv::COLOR_RGB2BGR);
  bool written = false;
  std::string reason = "the encoder reported failure (does the directory exist and is it writable?)";
  try {
    written = cv::imwrite(path, bgr);
  } catch (const cv::Exception& error) {
    reason = error.what();
  }
  if (!written) throw std::runtime_error("WritePng: cannot write '" + path + "': " + reason);
}

void WritePng(const std::string& path, const RgbImage& image) {
  WritePng(path, image.height, image.width, image.pixels.data());
}

RgbImage ReadPng(const std::string& path) {
  const cv::Mat bgr = cv::imread(path, cv::IMREAD_COLOR);
  if (bgr.empty()) throw std::runtime_error("ReadPng: cannot read '" + path + "' as an image");
  RgbImage image;
  image.height = bgr.rows;
  image.width = bgr.cols;
  image.pixels.resize(static_cast<std::size_t>(bgr.rows) * static_cast<std::size_t>(bgr.cols) * 3);
  cv::Mat rgb(bgr.rows, bgr.cols, CV_8UC3, image.pixels.data());
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  return image;
}

RgbImage MakeContactSheet(const std::vector<LabelledImage>& images) {
  if (images.empty()) throw std::invalid_argument("MakeContactSheet: no images");
  int cell_height = 0;
  int cell_width = 0;
  for (const LabelledImage& image : images) {
    RequireImage(("MakeContactSheet '" + image.label + "'").c_str(), image.height, image.width, image.rgb);
    cell_height = std::max(cell_height, image.height);
    cell_width = std::max(cell_width, image.width);
  }
  const int count = static_cast<int>(images.size());
  const int columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(count))));
  const int rows = (count + columns - 1) / columns;

  RgbImage sheet;
  sheet.height = rows * cell_height + (rows + 1) * kSheetMargin;
  sheet.width = columns * cell_width + (columns + 1) * kSheetMargin;
  sheet.pixels.resize(static_cast<std::size_t>(sheet.height) * static_cast<std::size_t>(sheet.width) * 3);
  cv::Mat canvas(sheet.height, sheet.width, CV_8UC3, sheet.pixels.data());
  canvas.setTo(kSheetBackground);
  for (int i = 0; i < count; ++i) {
    const LabelledImage& image = images[static_cast<std::size_t>(i)];
    const int x = kSheetMargin + (i % columns) * (cell_width + kSheetMargin);
    const int y = kSheetMargin + (i / columns) * (cell_height + kSheetMargin);
    cv::Mat cell = canvas(cv::Rect(x, y, image.width, image.height));
    RgbView(image.height, image.width, image.rgb).copyTo(cell);
    DrawLabel(&cell, image.label);
  }
  return sheet;
}

}  // namespace tavis::render
