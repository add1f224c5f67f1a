// The C++ side of the Python module's overhead benchmark (bench/python_overhead.py runs both):
// gym::GymVecEnv stepped from C++ with the work of the Python loop: 32 envs of clutter-pick-cube,
// the head and wrist cameras at 224 x 224, a trivial policy (the hold policy's first actions,
// held), autoreset on. Items are env steps.
#include <benchmark/benchmark.h>

#include <vector>

#include "batch/gym/gym_vec_env.h"
#include "kinematics/action.h"

namespace tavis::batch {
namespace {

constexpr int kEnvs = 32;

void BM_GymVecEnvStepFromCxx(benchmark::State& state) {
  gym::GymVecEnvConfig config;
  config.scene.task = "clutter-pick-cube";
  config.num_envs = kEnvs;
  config.scene.seed = 0;
  config.threads = static_cast<int>(state.range(0));
  config.scene.config_dir = TAVIS_CONFIG_DIR;
  gym::GymVecEnv env(config);
  env.Reset(std::vector<uint8_t>(kEnvs, 1), std::vector<int64_t>(kEnvs, -1));
  std::vector<double> actions(static_cast<std::size_t>(kEnvs) * kinematics::action::kSize);
  env.Act(*env.MakePolicy("hold", ""), actions.data());
  for (int warmup = 0; warmup < 3; ++warmup) env.Step(actions.data());
  for (auto _ : state) {
    env.Step(actions.data());
    benchmark::DoNotOptimize(env.agent_pos());
  }
  state.SetItemsProcessed(state.iterations() * kEnvs);
}
// threads 0: all cores, as the Python side's default.
BENCHMARK(BM_GymVecEnvStepFromCxx)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace tavis::batch
