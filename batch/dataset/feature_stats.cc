#include "batch/dataset/feature_stats.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tavis::batch::dataset {
namespace {

// numpy.quantile's default (linear) on sorted values.
double Quantile(const std::vector<double>& sorted, double level) {
  const double position = level * static_cast<double>(sorted.size() - 1);
  const std::size_t below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  return sorted[below] + (position - static_cast<double>(below)) * (sorted[above] - sorted[below]);
}

void Resize(FeatureStats& stats, std::size_t dims) {
  for (std::vector<double>* field :
       {&stats.min, &stats.max, &stats.mean, &stats.std, &stats.q01, &stats.q10, &stats.q50, &stats.q90, &stats.q99}) {
    field->assign(dims, 0.0);
  }
}

std::vector<double>* QuantileField(FeatureStats& stats, std::size_t level) {
  std::vector<double>* fields[] = {&stats.q01, &stats.q10, &stats.q50, &stats.q90, &stats.q99};
  return fields[level];
}

// The value at 0-based rank `rank` of a 256-bin histogram holding `total` values.
int HistogramRank(const std::array<int64_t, 256>& histogram, int64_t rank) {
  int64_t seen = 0;
  for (int value = 0; value < 256; ++value) {
    seen += histogram[static_cast<std::size_t>(value)];
    if (rank < seen) return value;
  }
  return 255;
}

}  // namespace

NumericStats::NumericStats(int dims) : dims_(dims), values_(static_cast<std::size_t>(dims)) {
  if (dims < 1) throw std::invalid_argument("a feature needs at least one dimension, got " + std::to_string(dims));
}

void NumericStats::Add(const float* row) {
  for (int d = 0; d < dims_; ++d) values_[static_cast<std::size_t>(d)].push_back(static_cast<double>(row[d]));
  ++count_;
}

void NumericStats::Add(double value) {
  if (dims_ != 1) throw std::logic_error("NumericStats::Add(double) is for scalar features");
  values_[0].push_back(value);
  ++count_;
}

void NumericStats::Merge(const NumericStats& other) {
  if (other.dims_ != dims_) throw std::logic_error("merging statistics of different dimensions");
  for (int d = 0; d < dims_; ++d) {
    std::vector<double>& mine = values_[static_cast<std::size_t>(d)];
    const std::vector<double>& theirs = other.values_[static_cast<std::size_t>(d)];
    mine.insert(mine.end(), theirs.begin(), theirs.end());
  }
  count_ += other.count_;
}

FeatureStats NumericStats::Compute() const {
  if (count_ == 0) throw std::logic_error("statistics of an empty feature");
  FeatureStats stats;
  stats.count = count_;
  Resize(stats, static_cast<std::size_t>(dims_));
  std::vector<double> sorted;
  for (std::size_t d = 0; d < static_cast<std::size_t>(dims_); ++d) {
    sorted = values_[d];
    std::sort(sorted.begin(), sorted.end());
    double sum = 0.0;
    for (double value : sorted) sum += value;
    const double mean = sum / static_cast<double>(sorted.size());
    double squares = 0.0;
    for (double value : sorted) squares += (value - mean) * (value - mean);
    stats.min[d] = sorted.front();
    stats.max[d] = sorted.back();
    stats.mean[d] = mean;
    stats.std[d] = std::sqrt(squares / static_cast<double>(sorted.size()));
    for (std::size_t level = 0; level < kQuantiles.size(); ++level) {
      (*QuantileField(stats, level))[d] = Quantile(sorted, kQuantiles[level]);
    }
  }
  return stats;
}

void ImageStats::AddFrame(const uint8_t* rgb, int width, int height) {
  const int stride = std::max(1, std::max(width, height) / 150);
  for (int y = 0; y < height; y += stride) {
    const uint8_t* row = rgb + static_cast<std::size_t>(y) * static_cast<std::size_t>(width) * 3;
    for (int x = 0; x < width; x += stride) {
      for (std::size_t c = 0; c < 3; ++c) ++histogram_[c][row[static_cast<std::size_t>(x) * 3 + c]];
    }
  }
  ++frames_;
}

ImageStats ImageStats::FromHistogram(int64_t frames, const Histogram& histogram) {
  ImageStats stats;
  stats.frames_ = frames;
  stats.histogram_ = histogram;
  return stats;
}

void ImageStats::Merge(const ImageStats& other) {
  for (std::size_t c = 0; c < 3; ++c) {
    for (std::size_t v = 0; v < 256; ++v) histogram_[c][v] += other.histogram_[c][v];
  }
  frames_ += other.frames_;
}

FeatureStats ImageStats::Compute() const {
  if (frames_ == 0) throw std::logic_error("statistics of an image feature with no frame");
  FeatureStats stats;
  stats.count = frames_;
  Resize(stats, 3);
  for (std::size_t c = 0; c < 3; ++c) {
    const std::array<int64_t, 256>& histogram = histogram_[c];
    int64_t total = 0;
    double sum = 0.0;
    for (std::size_t v = 0; v < 256; ++v) {
      total += histogram[v];
      sum += static_cast<double>(histogram[v]) * static_cast<double>(v);
    }
    const double mean = sum / static_cast<double>(total);
    double squares = 0.0;
    for (std::size_t v = 0; v < 256; ++v) {
      squares += static_cast<double>(histogram[v]) * (static_cast<double>(v) - mean) * (static_cast<double>(v) - mean);
    }
    stats.min[c] = HistogramRank(histogram, 0) / 255.0;
    stats.max[c] = HistogramRank(histogram, total - 1) / 255.0;
    stats.mean[c] = mean / 255.0;
    stats.std[c] = std::sqrt(squares / static_cast<double>(total)) / 255.0;
    for (std::size_t level = 0; level < kQuantiles.size(); ++level) {
      const double position = kQuantiles[level] * static_cast<double>(total - 1);
      const int64_t below = static_cast<int64_t>(std::floor(position));
      const double low = HistogramRank(histogram, below);
      const double high = HistogramRank(histogram, std::min(below + 1, total - 1));
      (*QuantileField(stats, level))[c] = (low + (position - static_cast<double>(below)) * (high - low)) / 255.0;
    }
  }
  return stats;
}

}  // namespace tavis::batch::dataset
