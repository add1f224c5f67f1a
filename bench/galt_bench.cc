// GALT throughput over an evaluation-sized batch: 10,000 episodes of 400 policy steps at 20 Hz
// (20 s, the evaluation cap). Target: >= 20,000 episodes/s on 2 threads (items_per_second).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <random>
#include <vector>

#include "kinematics/galt.h"

namespace tavis::kinematics {
namespace {

constexpr int kEpisodes = 10000;
constexpr int kSteps = 400;
constexpr double kFps = 20.0;
// Distinct trajectories behind the 10,000 views (61 MB, far beyond the caches); 10,000
// distinct ones would take 608 MB for no difference in the work done.
constexpr int kDistinctEpisodes = 1000;

// A teleop-like episode: the head turns to a target and settles with sensor-like jitter, then
// one hand rests, reaches, grasps and lifts; event times and targets are random.
std::vector<double> SyntheticEpisode(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> jitter(0.0, 0.0005);
  const int head_settle = 20 + static_cast<int>(unit(rng) * 100);
  const int reach_onset = head_settle + 10 + static_cast<int>(unit(rng) * 60);
  const int grasp = reach_onset + 15 + static_cast<int>(unit(rng) * 25);
  const int lift_end = std::min(kSteps - 1, grasp + 30);
  const double yaw = unit(rng) - 0.5;
  const double pitch = 0.3 + 0.4 * unit(rng);
  const int ee = unit(rng) < 0.5 ? action::kArmPosition[0] : action::kArmPosition[1];
  const int gripper = ee == action::kArmPosition[0] ? action::kGripper[0] : action::kGripper[1];

  std::vector<double> episode(static_cast<std::size_t>(kSteps) * action::kSize, 0.0);
  for (int t = 0; t < kSteps; ++t) {
    double* row = &episode[static_cast<std::size_t>(t) * action::kSize];
    const double head = std::min(1.0, static_cast<double>(t) / head_settle);
    row[action::kNeckYaw] = head * yaw + jitter(rng);
    row[action::kNeckPitch] = head * pitch + jitter(rng);
    const double reach = std::clamp(static_cast<double>(t - reach_onset) / (grasp - reach_onset), 0.0, 1.0);
    const double lift = std::clamp(static_cast<double>(t - grasp) / (lift_end - grasp), 0.0, 1.0);
    row[ee + 0] = 0.2 + 0.25 * reach;
    row[ee + 1] = 0.1 * reach;
    row[ee + 2] = 0.1 + 0.15 * lift;
    row[action::kArmQuaternion[0]] = 1.0;
    row[action::kArmQuaternion[1]] = 1.0;
    row[action::kGripper[0]] = -1.0;
    row[action::kGripper[1]] = -1.0;
    row[gripper] = t >= grasp ? 1.0 : -1.0;
  }
  return episode;
}

void BM_GaltBatch(benchmark::State& state) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  std::mt19937 rng(42);
  std::vector<std::vector<double>> distinct;
  for (int i = 0; i < kDistinctEpisodes; ++i) distinct.push_back(SyntheticEpisode(rng));
  std::vector<TrajectoryView> episodes;
  for (int i = 0; i < kEpisodes; ++i) {
    episodes.push_back({distinct[static_cast<std::size_t>(i % kDistinctEpisodes)].data(), kSteps, action::kSize});
  }

  int valid = 0;
  for (auto _ : state) {
    const std::vector<GaltResult> results = ComputeGaltBatch(episodes, kFps);
    valid = static_cast<int>(
        std::count_if(results.begin(), results.end(), [](const GaltResult& r) { return r.galt_s.has_value(); }));
    benchmark::DoNotOptimize(valid);
  }
  state.SetItemsProcessed(state.iterations() * kEpisodes);
  state.counters["valid_fraction"] = static_cast<double>(valid) / kEpisodes;
}
BENCHMARK(BM_GaltBatch)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace tavis::kinematics
