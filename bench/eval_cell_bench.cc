// A full evaluation cell as `tavis eval` runs it by default: clutter-pick-cube, `id` split,
// scripted expert, seed 0, 96 episodes over 32 env slots, on 2 threads. One cell per iteration;
// use --benchmark_repetitions=N for a spread. Counters: episodes/s, env control ticks/s (60 Hz
// ticks simulated per wall second) and the cell's success rate.
//
// BM_EvalCellRendering is the same cell while the head and both wrist cameras are rendered at
// 224x224 on every policy tick (20 Hz), as a learned policy would see them; the expert ignores the
// images, which are discarded. Extra counter: rendered images per second.
//
// BM_AllIdExpertCells is the sweep a researcher runs to validate the experts: all 16 `id`
// cells (eight tasks x two robots, 96 episodes each, no rendering) one after another; its time is
// the whole sweep (target: at most 5 minutes on 2 threads).
//
// Run: tavis_eval_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cstdint>
#include <string>
#include <vector>

#include "batch/cell/evaluation_cell.h"
#include "scenarios/registry.h"

namespace tavis::batch {
namespace {

cell::EvaluationCellConfig DefaultCell(const char* robot) {
  cell::EvaluationCellConfig config;
  config.task = "clutter-pick-cube";
  config.robot = robot;
  config.split = scenarios::Split::kId;
  config.policy = "expert";
  config.episodes = 96;
  config.envs = 32;
  config.seed = 0;
  config.config_dir = TAVIS_CONFIG_DIR;
  return config;
}

void RunCells(benchmark::State& state, const cell::EvaluationCellConfig& config) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
  double wall_s = 0.0;
  int64_t episodes = 0;
  int64_t successes = 0;
  int64_t control_ticks = 0;
  int64_t images = 0;
  for (auto _ : state) {
    const cell::CellResult result = cell::RunEvaluationCell(config);
    wall_s += result.wall_s;
    episodes += static_cast<int64_t>(result.episodes.size());
    successes += result.successes;
    control_ticks += result.control_ticks;
    images += result.rendered_images;
    benchmark::DoNotOptimize(result.successes);
  }
  state.counters["episodes/s"] = static_cast<double>(episodes) / wall_s;
  state.counters["ticks/s"] = static_cast<double>(control_ticks) / wall_s;
  state.counters["success_rate"] = static_cast<double>(successes) / static_cast<double>(episodes);
  state.counters["cell_wall_s"] = wall_s / static_cast<double>(state.iterations());
  if (images > 0) state.counters["images/s"] = static_cast<double>(images) / wall_s;
}

void BM_EvalCell(benchmark::State& state, const char* robot) { RunCells(state, DefaultCell(robot)); }

void BM_EvalCellRendering(benchmark::State& state, const char* robot) {
  cell::EvaluationCellConfig config = DefaultCell(robot);
  config.render_cameras = {"head", "left_wrist", "right_wrist"};
  config.image_width = 224;
  config.image_height = 224;
  RunCells(state, config);
}

void BM_AllIdExpertCells(benchmark::State& state) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
  int64_t episodes = 0;
  int64_t successes = 0;
  int64_t control_ticks = 0;
  for (auto _ : state) {
    for (const char* robot : {"gr1t2", "reachy2"}) {
      for (const scenarios::ScenarioDef& scenario : scenarios::AllScenarios()) {
        cell::EvaluationCellConfig config = DefaultCell(robot);
        config.task = scenario.name;
        const cell::CellResult result = cell::RunEvaluationCell(config);
        episodes += static_cast<int64_t>(result.episodes.size());
        successes += result.successes;
        control_ticks += result.control_ticks;
      }
    }
  }
  state.counters["cells"] = 2.0 * static_cast<double>(scenarios::AllScenarios().size());
  state.counters["ticks/s"] = benchmark::Counter(static_cast<double>(control_ticks), benchmark::Counter::kIsRate);
  state.counters["success_rate"] = static_cast<double>(successes) / static_cast<double>(episodes);
}

BENCHMARK_CAPTURE(BM_EvalCell, gr1t2, "gr1t2")->UseRealTime()->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_EvalCell, reachy2, "reachy2")->UseRealTime()->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_EvalCellRendering, gr1t2, "gr1t2")->UseRealTime()->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_EvalCellRendering, reachy2, "reachy2")->UseRealTime()->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_AllIdExpertCells)->UseRealTime()->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
}  // namespace tavis::batch
