#include "batch/cell/motion_quality.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>

namespace tavis::batch::cell {
namespace {

// In-place iterative radix-2 FFT (Cooley-Tukey); data.size() is a power of two. Twiddles come from
// std::cos and std::sin of each angle (no recurrence), so the result does not drift with size.
void Fft(std::vector<std::complex<double>>& data) {
  const std::size_t n = data.size();
  for (std::size_t i = 1, j = 0; i < n; ++i) {
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(data[i], data[j]);
  }
  for (std::size_t length = 2; length <= n; length <<= 1) {
    const double angle = -2.0 * M_PI / static_cast<double>(length);
    for (std::size_t start = 0; start < n; start += length) {
      for (std::size_t k = 0; k < length / 2; ++k) {
        const double a = angle * static_cast<double>(k);
        const std::complex<double> twiddle(std::cos(a), std::sin(a));
        const std::complex<double> odd = twiddle * data[start + k + length / 2];
        data[start + k + length / 2] = data[start + k] - odd;
        data[start + k] += odd;
      }
    }
  }
}

}  // namespace

std::optional<double> SpectralArcLength(const std::vector<double>& speed, double sample_hz,
                                        const SparcSettings& settings) {
  if (speed.size() < 2) return std::nullopt;
  const int bits = static_cast<int>(std::ceil(std::log2(static_cast<double>(speed.size())))) + settings.pad_level;
  const std::size_t nfft = std::size_t{1} << bits;
  std::vector<std::complex<double>> spectrum(nfft);
  std::copy(speed.begin(), speed.end(), spectrum.begin());
  Fft(spectrum);
  double peak = 0.0;
  for (const std::complex<double>& value : spectrum) peak = std::max(peak, std::abs(value));
  if (!(peak > 0.0)) return std::nullopt;
  // The bins up to the maximum cut-off, then the adaptive cut-off: from the first to the last of
  // them whose normalised magnitude reaches the threshold.
  const double bin_hz = sample_hz / static_cast<double>(nfft);
  std::vector<double> magnitude;
  for (std::size_t k = 0; k < nfft && static_cast<double>(k) * bin_hz <= settings.max_cutoff_hz; ++k)
    magnitude.push_back(std::abs(spectrum[k]) / peak);
  std::size_t first = magnitude.size(), last = 0;
  for (std::size_t k = 0; k < magnitude.size(); ++k) {
    if (magnitude[k] < settings.amplitude_threshold) continue;
    first = std::min(first, k);
    last = k;
  }
  if (first >= magnitude.size() || last == first) return 0.0;
  const double band = static_cast<double>(last - first);  // in bins: the frequency axis normalised to it
  double length = 0.0;
  for (std::size_t k = first + 1; k <= last; ++k) {
    const double df = 1.0 / band;
    const double dm = magnitude[k] - magnitude[k - 1];
    length += std::sqrt(df * df + dm * dm);
  }
  return -length;
}

double RmsJerk(const std::vector<Vec3>& positions, double sample_hz) {
  if (positions.size() < 4) return 0.0;
  const double scale = sample_hz * sample_hz * sample_hz;
  double sum = 0.0;
  for (std::size_t i = 0; i + 3 < positions.size(); ++i) {
    const Vec3 jerk = (positions[i + 3] - 3.0 * positions[i + 2] + 3.0 * positions[i + 1] - positions[i]) * scale;
    sum += jerk.squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(positions.size() - 3));
}

double PathLength(const std::vector<Vec3>& positions) {
  double length = 0.0;
  for (std::size_t i = 1; i < positions.size(); ++i) length += (positions[i] - positions[i - 1]).norm();
  return length;
}

ArmMotion MeasureArmMotion(const std::vector<Vec3>& positions, double sample_hz) {
  ArmMotion motion;
  motion.path_m = PathLength(positions);
  motion.jerk_rms = RmsJerk(positions, sample_hz);
  if (motion.path_m < kMinSparcPath) return motion;
  std::vector<double> speed;
  speed.reserve(positions.size());
  for (std::size_t i = 1; i < positions.size(); ++i)
    speed.push_back((positions[i] - positions[i - 1]).norm() * sample_hz);
  motion.sparc = SpectralArcLength(speed, sample_hz);
  return motion;
}

}  // namespace tavis::batch::cell
