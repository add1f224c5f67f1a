// Counter-based random numbers: every draw is a pure function of (key, counter), so a result
// never depends on the thread count or on which thread ran which env. Keys are derived from
// (seed, stream, episode index) with SplitMix64 mixing.
#pragma once

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace tavis::engine {

constexpr uint64_t MixBits(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

constexpr uint64_t DeriveKey(uint64_t seed, uint64_t stream, uint64_t index) {
  return MixBits(MixBits(MixBits(seed) ^ stream) ^ index);
}

// Named streams so that adding draws to one purpose never shifts another's numbers. The scene
// perturbation axes (docs/perturbations.md) draw from streams of their own, so that the task's
// draws, and with them the base scene, stay the same under them.
enum class RandomStreamId : uint64_t {
  kTask = 1,
  kInitPose = 2,
  kSensorNoise = 3,
  kPerturbation = 4,
  kDistractors = 5,  // which distractors an episode gets, where they stand
  kParaphrase = 6,   // which paraphrase of its prompt an episode gets
  kTargetMove = 7,   // which way the runtime axis moves an episode's target
  kAppearance = 8,  // the appearance axis's random texture colours
};

class RandomStream {
 public:
  RandomStream() = default;
  RandomStream(uint64_t seed, RandomStreamId stream, uint64_t episode)
      : key_(DeriveKey(seed, static_cast<uint64_t>(stream), episode)) {}

  uint64_t NextBits() { return MixBits(key_ ^ MixBits(counter_++)); }
  // Uniform in [0, 1) with 53 random bits.
  double Uniform() { return static_cast<double>(NextBits() >> 11) * 0x1.0p-53; }
  double Uniform(double low, double high) { return low + (high - low) * Uniform(); }
  // Uniform integer in [0, n).
  int UniformInt(int n) { return static_cast<int>(Uniform() * n); }
  double Normal(double mean, double stddev) {
    // Box-Muller; 1 - Uniform() lies in (0, 1], so the logarithm is finite.
    const double radius = std::sqrt(-2.0 * std::log(1.0 - Uniform()));
    return mean + stddev * radius * std::cos(2.0 * M_PI * Uniform());
  }
  // random.sample(range(n), k): k distinct indices in draw order (partial Fisher-Yates); the
  // remaining n - k follow, so the result is a permutation of 0..n-1.
  std::vector<int> Sample(int n, int k) {
    std::vector<int> order(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) order[static_cast<size_t>(i)] = i;
    for (int i = 0; i < k; ++i)
      std::swap(order[static_cast<size_t>(i)], order[static_cast<size_t>(i + UniformInt(n - i))]);
    return order;
  }
  uint32_t counter() const { return static_cast<uint32_t>(counter_); }

 private:
  uint64_t key_ = 0;
  uint64_t counter_ = 0;
};

}  // namespace tavis::engine
