// Motion quality (batch/cell/motion_quality.h) against references computed by hand or by the
// authors' published SPARC code, on synthetic trajectories sampled at the 60 Hz control rate.
#include "batch/cell/motion_quality.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace tavis::batch::cell {
namespace {

constexpr double kHz = 60.0;

// A minimum-jerk reach of `distance` m along x in `duration` s, starting at `start` s, sampled at
// 60 Hz over [0, total] s.
std::vector<Vec3> MinimumJerkReach(double distance, double duration, double start, double total) {
  std::vector<Vec3> positions;
  for (int i = 0; i <= static_cast<int>(std::lround(total * kHz)); ++i) {
    const double tau = std::clamp((i / kHz - start) / duration, 0.0, 1.0);
    positions.push_back(Vec3(distance * (10 * std::pow(tau, 3) - 15 * std::pow(tau, 4) + 6 * std::pow(tau, 5)), 0, 0));
  }
  return positions;
}

std::vector<double> Speeds(const std::vector<Vec3>& positions) {
  std::vector<double> speed;
  for (std::size_t i = 1; i < positions.size(); ++i) speed.push_back((positions[i] - positions[i - 1]).norm() * kHz);
  return speed;
}

// The SPARC values below are the output of Balasubramanian et al.'s published Python function
// (sparc(movement, fs, padlevel=4, fc=10.0, amp_th=0.05), numpy 1.24) on the same samples.
TEST(MotionQuality, SparcOfAMinimumJerkReachMatchesTheAuthorsCode) {
  const std::vector<double> speed = Speeds(MinimumJerkReach(0.3, 1.0, 0.5, 2.0));
  ASSERT_EQ(speed.size(), 120u);
  EXPECT_NEAR(*SpectralArcLength(speed, kHz), -1.4005808238778379, 1e-9);
}

TEST(MotionQuality, SparcOfTwoSubmovementsIsLowerAndMatchesTheAuthorsCode) {
  const std::vector<Vec3> first = MinimumJerkReach(0.15, 0.6, 0.3, 2.0);
  const std::vector<Vec3> second = MinimumJerkReach(0.15, 0.6, 1.1, 2.0);
  std::vector<Vec3> both;
  for (std::size_t i = 0; i < first.size(); ++i) both.push_back(first[i] + second[i]);
  EXPECT_NEAR(*SpectralArcLength(Speeds(both), kHz), -2.906302832909955, 1e-9);
}

TEST(MotionQuality, SparcOfASineSpeedProfileMatchesTheAuthorsCode) {
  std::vector<double> speed;
  for (int i = 0; i < 120; ++i) speed.push_back(1.0 + std::sin(2 * M_PI * 2 * i / kHz));
  EXPECT_NEAR(*SpectralArcLength(speed, kHz), -3.345811668267031, 1e-9);
}

TEST(MotionQuality, AStandingArmHasNoSparc) {
  EXPECT_FALSE(SpectralArcLength(std::vector<double>(50, 0.0), kHz));
  const ArmMotion still = MeasureArmMotion(std::vector<Vec3>(50, Vec3(0.3, 0.2, 1.0)), kHz);
  EXPECT_EQ(still.path_m, 0.0);
  EXPECT_NEAR(still.jerk_rms, 0.0, 1e-9);
  EXPECT_FALSE(still.sparc);
}

// A minimum-jerk reach of D in T: jerk(t) = D/T^3 (60 - 360 tau + 360 tau^2), whose square
// integrates to 720 D^2 / T^5 over the reach (0 at rest before and after), so the RMS over the
// n - 3 third differences of n samples is sqrt(720 D^2 / T^5 / ((n - 3) / 60 Hz)). Finite
// differences at 60 Hz smooth the jerk's steps at the reach's start and end: 2.4% here.
TEST(MotionQuality, RmsJerkOfAMinimumJerkReachIsTheClosedForm) {
  const double distance = 0.3, duration = 1.0;
  const std::vector<Vec3> reach = MinimumJerkReach(distance, duration, 0.5, 2.0);
  const double seconds = static_cast<double>(reach.size() - 3) / kHz;
  const double expected = std::sqrt(720.0 * distance * distance / std::pow(duration, 5) / seconds);
  EXPECT_NEAR(RmsJerk(reach, kHz), expected, 0.03 * expected);
  EXPECT_NEAR(PathLength(reach), distance, 1e-12);
}

// p = A sin(w t) along y: jerk = -A w^3 cos(w t), RMS over whole periods A w^3 / sqrt(2); the path
// over one period is 4 A.
TEST(MotionQuality, RmsJerkAndPathOfASineAreTheClosedForm) {
  const double amplitude = 0.05, w = 2 * M_PI * 0.5;
  std::vector<Vec3> positions;
  for (int i = 0; i <= 240; ++i) positions.push_back(Vec3(0, amplitude * std::sin(w * i / kHz), 1.0));
  const double expected = amplitude * std::pow(w, 3) / std::sqrt(2.0);
  EXPECT_NEAR(RmsJerk(positions, kHz), expected, 0.01 * expected);
  EXPECT_NEAR(PathLength(positions), 8 * amplitude, 1e-3);
  const ArmMotion motion = MeasureArmMotion(positions, kHz);
  EXPECT_EQ(motion.path_m, PathLength(positions));
  ASSERT_TRUE(motion.sparc);
  EXPECT_EQ(*motion.sparc, *SpectralArcLength(Speeds(positions), kHz));
}

}  // namespace
}  // namespace tavis::batch::cell
