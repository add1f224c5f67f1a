#include "render/image_io.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/core.hpp>
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

// libpng's simplified interface for tightly packed 8-bit RGB rows. Fast compression: the files
// are frames and figures written in bulk, as OpenCV's default (level 1) wrote them before.
png_image RgbPngHeader(int height, int width) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(width);
  image.height = static_cast<png_uint_32>(height);
  image.format = PNG_FORMAT_RGB;
  image.flags = PNG_IMAGE_FLAG_FAST;
  return image;
}

// Why libpng failed (for a file it could not open, strerror's text), read before it is freed.
std::string FailureReason(png_image* image) {
  std::string reason = image->message;
  png_image_free(image);
  return reason;
}

}  // namespace

void WritePng(const std::string& path, int height, int width, const uint8_t* rgb) {
  RequireImage(("WritePng '" + path + "'").c_str(), height, width, rgb);
  png_image image = RgbPngHeader(height, width);
  if (png_image_write_to_file(&image, path.c_str(), 0, rgb, 0, nullptr) == 0) {
    throw std::runtime_error("WritePng: cannot write '" + path + "': " + FailureReason(&image));
  }
}

void WritePng(const std::string& path, const RgbImage& image) {
  WritePng(path, image.height, image.width, image.pixels.data());
}

std::string EncodePng(int height, int width, const uint8_t* rgb) {
  RequireImage("EncodePng", height, width, rgb);
  png_image image = RgbPngHeader(height, width);
  png_alloc_size_t size = 0;
  auto encode = [&](void* memory) {
    if (png_image_write_to_memory(&image, memory, &size, 0, rgb, 0, nullptr) == 0) {
      throw std::runtime_error("EncodePng: cannot encode a " + std::to_string(height) + "x" + std::to_string(width) +
                               " image: " + FailureReason(&image));
    }
  };
  encode(nullptr);  // measures
  std::string bytes(size, '\0');
  encode(bytes.data());
  bytes.resize(size);
  return bytes;
}

RgbImage ReadPng(const std::string& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_file(&image, path.c_str()) == 0) {
    throw std::runtime_error("ReadPng: cannot read '" + path + "' as a PNG image: " + FailureReason(&image));
  }
  // Whatever the file holds (grey, palette, alpha, 16 bits), 8-bit RGB comes out; an alpha
  // channel is composited onto black.
  image.format = PNG_FORMAT_RGB;
  RgbImage read;
  read.height = static_cast<int>(image.height);
  read.width = static_cast<int>(image.width);
  read.pixels.resize(PNG_IMAGE_SIZE(image));
  const png_color black{0, 0, 0};
  if (png_image_finish_read(&image, &black, read.pixels.data(), 0, nullptr) == 0) {
    throw std::runtime_error("ReadPng: cannot read '" + path + "' as a PNG image: " + FailureReason(&image));
  }
  return read;
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
