// How an arm moved in an episode, from its tool centre point's world position sampled at every
// control tick (60 Hz): the path length, the jerk and the smoothness of its speed profile (SPARC).
// Definitions (docs/events.md, "Motion quality"):
//   path_m    the sum of the distances between consecutive samples (m);
//   jerk_rms  the root mean square, over the episode's third differences, of the magnitude of the
//             position's third derivative by finite differences, |p[i+3] - 3p[i+2] + 3p[i+1] - p[i]|
//             / dt^3 (m/s^3);
//   sparc     the spectral arc length of the speed profile (Balasubramanian et al. 2015, "On the
//             analysis of movement smoothness", J. NeuroEng. Rehabil. 12:112): the arc length of
//             the speed's Fourier magnitude spectrum, normalised to its peak, zero-padded to
//             2^(ceil(log2 n) + 4) points, from 0 Hz up to the adaptive cut-off (the last frequency
//             below 10 Hz whose magnitude is at least 0.05), with the frequency axis normalised to
//             that band; negative, closer to 0 is smoother. None for an arm that did not move.
#pragma once

#include <optional>
#include <vector>

#include "kinematics/pose.h"

namespace tavis::batch::cell {

struct SparcSettings {
  double max_cutoff_hz = 10.0;
  double amplitude_threshold = 0.05;
  int pad_level = 4;  // zero-padding: the FFT has 2^(ceil(log2 n) + pad_level) points
};

// SPARC of a speed profile sampled at `sample_hz`; none when it has fewer than 2 samples or no
// motion (every speed 0).
std::optional<double> SpectralArcLength(const std::vector<double>& speed, double sample_hz,
                                        const SparcSettings& settings = {});

// The RMS jerk magnitude (m/s^3) of positions sampled every 1/sample_hz s; 0 with fewer than 4.
double RmsJerk(const std::vector<Vec3>& positions, double sample_hz);

double PathLength(const std::vector<Vec3>& positions);

// An arm's motion quality in one episode.
struct ArmMotion {
  double path_m = 0.0;
  double jerk_rms = 0.0;
  std::optional<double> sparc;  // none when the arm moved less than kMinSparcPath

  bool operator==(const ArmMotion& other) const {
    return path_m == other.path_m && jerk_rms == other.jerk_rms && sparc == other.sparc;
  }
};

// An arm whose tool centre point travelled less than this has no SPARC: the spectrum of a
// standing arm's numerical jitter says nothing about a movement.
inline constexpr double kMinSparcPath = 0.01;  // m

// The three measures of one arm's positions sampled at `sample_hz` (the speed profile is the
// distance between consecutive samples times the rate).
ArmMotion MeasureArmMotion(const std::vector<Vec3>& positions, double sample_hz);

}  // namespace tavis::batch::cell
