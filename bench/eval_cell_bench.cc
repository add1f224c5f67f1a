// A full evaluation cell as `tavis eval` runs it by default: clutter-pick-cube, `id` split,
// scripted expert, seed 0, 96 episodes over 32 env slots, on 2 threads. One cell per iteration;
// use --benchmark_repetitions=N for a spread. Counters: episodes/s, env control ticks/s (60 Hz
// ticks simulated per wall second) and the cell's success rate.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cstdint>

#include "batch/evaluation_cell.h"

namespace tavis::batch {
namespace {

void BM_EvalCell(benchmark::State& state, const char* robot) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
  EvaluationCellConfig config;
  config.task = "clutter-pick-cube";
  config.robot = robot;
  config.split = scenarios::Split::kId;
  config.policy = "expert";
  config.episodes = 96;
  config.envs = 32;
  config.seed = 0;
  config.config_dir = TAVIS_CONFIG_DIR;

  double wall_s = 0.0;
  int64_t episodes = 0;
  int64_t successes = 0;
  int64_t control_ticks = 0;
  for (auto _ : state) {
    const CellResult result = RunEvaluationCell(config);
    wall_s += result.wall_s;
    episodes += static_cast<int64_t>(result.episodes.size());
    successes += result.successes;
    control_ticks += result.control_ticks;
    benchmark::DoNotOptimize(result.successes);
  }
  state.counters["episodes/s"] = static_cast<double>(episodes) / wall_s;
  state.counters["ticks/s"] = static_cast<double>(control_ticks) / wall_s;
  state.counters["success_rate"] = static_cast<double>(successes) / static_cast<double>(episodes);
  state.counters["cell_wall_s"] = wall_s / static_cast<double>(state.iterations());
}

BENCHMARK_CAPTURE(BM_EvalCell, gr1t2, "gr1t2")->UseRealTime()->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_EvalCell, reachy2, "reachy2")->UseRealTime()->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
}  // namespace tavis::batch
