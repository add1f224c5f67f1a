// Normalisation statistics of dataset features as LeRobot writes them (lerobot-v3-format.md
// section 4): per dimension min, max, mean, std and the quantiles q01, q10, q50, q90, q99, plus the
// count. LeRobot estimates quantiles from histograms; ours are exact: numeric features keep every
// value (a dataset's numeric columns are small), and images are uint8, so a 256-bin histogram per
// channel is exact. Image statistics are in [0, 1] (pixel / 255), per channel, over the pixels of
// every frame sampled on a grid whose long side is about 150 px, as LeRobot downsamples.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace tavis::batch::dataset {

struct FeatureStats {
  std::vector<double> min, max, mean, std, q01, q10, q50, q90, q99;  // (dims)
  int64_t count = 0;                                                 // rows, or frames for an image feature
};

// The quantile levels, in the order of FeatureStats' q fields.
inline constexpr std::array<double, 5> kQuantiles = {0.01, 0.10, 0.50, 0.90, 0.99};

class NumericStats {
 public:
  explicit NumericStats(int dims);

  int dims() const { return dims_; }
  int64_t count() const { return count_; }
  void Add(const float* row);
  void Add(double value);  // a scalar feature (dims 1)
  void Merge(const NumericStats& other);
  // Exact statistics (population std, quantiles by linear interpolation as numpy's default).
  // Throws std::logic_error when nothing was added.
  FeatureStats Compute() const;

 private:
  int dims_;
  int64_t count_ = 0;
  std::vector<std::vector<double>> values_;  // [dim][row]
};

class ImageStats {
 public:
  // Adds one RGB frame (width x height x 3, row-major).
  void AddFrame(const uint8_t* rgb, int width, int height);
  void Merge(const ImageStats& other);
  int64_t frames() const { return frames_; }
  // Three dimensions (r, g, b) in [0, 1]; count = frames. Throws std::logic_error when empty.
  FeatureStats Compute() const;

  using Histogram = std::array<std::array<int64_t, 256>, 3>;  // [channel][value] sampled pixels
  const Histogram& histogram() const { return histogram_; }
  // The statistics of `frames` frames whose sampled pixels are `histogram` (as saved elsewhere).
  static ImageStats FromHistogram(int64_t frames, const Histogram& histogram);

 private:
  int64_t frames_ = 0;
  Histogram histogram_{};
};

}  // namespace tavis::batch::dataset
