// PNG files (through libpng) and labelled contact sheets of RGB images (height x width x 3 uint8, row-major).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tavis::render {

struct RgbImage {
  int height = 0;
  int width = 0;
  std::vector<uint8_t> pixels;  // height x width x 3
};

// Throws std::invalid_argument for a non-positive size or null pixels, std::runtime_error naming
// the path when the file cannot be written.
void WritePng(const std::string& path, int height, int width, const uint8_t* rgb);
void WritePng(const std::string& path, const RgbImage& image);

// The PNG file's bytes, as WritePng writes them (for figures embedded in other files).
// Throws std::invalid_argument for a non-positive size or null pixels.
std::string EncodePng(int height, int width, const uint8_t* rgb);

// Any PNG (grey, palette, 16 bits; alpha composited onto black) as 8-bit RGB. Throws
// std::runtime_error naming the path and libpng's reason when it cannot be read as a PNG.
RgbImage ReadPng(const std::string& path);

struct LabelledImage {
  std::string label;
  int height = 0;
  int width = 0;
  const uint8_t* rgb = nullptr;
};

// Tiles the images in a grid (two columns for four views: head, fixed / left wrist, right wrist)
// on a dark background, each cell as large as the largest image, with its label drawn in the
// top-left corner. Throws std::invalid_argument for an empty list or an invalid image.
RgbImage MakeContactSheet(const std::vector<LabelledImage>& images);

}  // namespace tavis::render
