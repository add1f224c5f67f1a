// The pick expert allocates no heap memory on the control ticks between its plans: planning a
// peek or a grasp may allocate, moving the hands and the head along the plan must not (every
// env runs Act at every control tick). This binary replaces the global operator new/delete with
// versions that count the calling thread's allocations, and runs the expert through whole
// physics episodes with batch::VecEnv.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "batch/vec_env.h"
#include "scenarios/expert/pick_expert.h"
#include "scenarios/registry.h"
#include "tests/support/robot_loading.h"

namespace {

thread_local long t_allocations = 0;  // operator new calls on this thread

void* CountedAllocation(std::size_t size) noexcept {
  ++t_allocations;
  return std::malloc(size == 0 ? 1 : size);
}

void* CountedAlignedAllocation(std::size_t size, std::align_val_t alignment) noexcept {
  ++t_allocations;
  const auto align = static_cast<std::size_t>(alignment);
  return std::aligned_alloc(align, (size + align - 1) / align * align);  // a multiple of the alignment
}

}  // namespace

void* operator new(std::size_t size) {
  if (void* p = CountedAllocation(size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  if (void* p = CountedAllocation(size)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, std::align_val_t alignment) {
  if (void* p = CountedAlignedAllocation(size, alignment)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size, std::align_val_t alignment) {
  if (void* p = CountedAlignedAllocation(size, alignment)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return CountedAllocation(size); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return CountedAllocation(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

namespace tavis::scenarios::expert {
namespace {

using Phase = PickExpert::Phase;
constexpr std::size_t kPhases = static_cast<std::size_t>(Phase::kGiveUp) + 1;
constexpr std::array<const char*, kPhases> kPhaseNames = {
    "watch-cue", "look", "settle", "peek", "approach", "descend", "close", "withdraw", "lift", "retreat", "give-up"};

// What one episode's Act calls allocated. A planning tick is one on which the expert planned: it
// started a grasp (its attempts went up) or a peek (it entered kPeek). Every other tick is
// counted under the phase it started in.
struct ActAllocations {
  std::array<long, kPhases> steady{};  // allocations on ticks that did not plan
  std::array<int, kPhases> steady_ticks{};
  int planning_ticks = 0;
  int attempts = 0;
};

// How the expert reads its grippers: as simulated, or shut on nothing whenever it commands one
// closed (every grasp misses: the expert retreats and plans again).
enum class GripReading { kSimulated, kClosedOnNothing };

ActAllocations RunEpisode(const std::string& task, const std::string& robot_name, int64_t episode, GripReading grip) {
  const ScenarioDef& scenario = FindScenario(task);
  const kinematics::RobotModel robot = tavis::testing::LoadRobot(robot_name);
  batch::VecEnv vec_env(batch::BuildWorldModel(robot, scenario), scenario, Split::kId, 1, 0);
  const std::unique_ptr<Expert> made = scenario.make_expert(vec_env.model(), 1, ExpertMode::kGazeFirst);
  PickExpert& expert = dynamic_cast<PickExpert&>(*made);
  vec_env.ResetEnv(0, episode);
  expert.Reset(vec_env.model(), vec_env.state(), 0);
  std::vector<kinematics::Action> actions(1);
  engine::BatchState read;  // the state the expert reads, with kClosedOnNothing
  ActAllocations result;
  while (vec_env.state().end[0] == engine::EpisodeEnd::kRunning) {
    if (grip == GripReading::kClosedOnNothing) {
      read = vec_env.state();
      for (const kinematics::Side side : kinematics::kSides) {
        const int i = kinematics::Index(side);
        if (actions[0][kinematics::action::kGripper[i]] > 0.0) read.gripper_gap_row(0)[i] = robot.gripper.closed_gap;
      }
    }
    const engine::BatchState& state = grip == GripReading::kClosedOnNothing ? read : vec_env.state();
    const Phase phase = expert.phase(0);
    const int attempts = expert.attempts(0);
    const long allocations_before = t_allocations;
    expert.Act(vec_env.model(), state, 0, actions[0]);
    const long allocations = t_allocations - allocations_before;
    const bool planned = expert.attempts(0) > attempts || (expert.phase(0) == Phase::kPeek && phase != Phase::kPeek);
    if (planned) {
      ++result.planning_ticks;
    } else {
      result.steady[static_cast<std::size_t>(phase)] += allocations;
      ++result.steady_ticks[static_cast<std::size_t>(phase)];
    }
    vec_env.Step(actions);
  }
  result.attempts = expert.attempts(0);
  return result;
}

// Checks that no steady tick allocated; adds the episode's steady ticks to `ticks`.
void ExpectSteadyTicksAllocateNothing(const ActAllocations& run, const std::string& label,
                                      std::array<int, kPhases>& ticks) {
  EXPECT_GT(run.planning_ticks, 0) << label;
  for (std::size_t p = 0; p < kPhases; ++p) {
    EXPECT_EQ(run.steady[p], 0) << label << ": " << run.steady[p] << " allocations in " << run.steady_ticks[p]
                                << " ticks of phase " << kPhaseNames[p];
    ticks[p] += run.steady_ticks[p];
  }
}

TEST(PickExpertAllocation, TicksBetweenPlansAllocateNothingInWholeEpisodes) {
  std::array<int, kPhases> ticks{};
  long allocations = 0;
  for (const char* robot : {"gr1t2", "reachy2"}) {
    for (const ScenarioDef& scenario : AllScenarios()) {
      const ActAllocations run = RunEpisode(scenario.name, robot, /*episode=*/0, GripReading::kSimulated);
      ExpectSteadyTicksAllocateNothing(run, scenario.name + " on " + robot, ticks);
      for (const long phase_allocations : run.steady) allocations += phase_allocations;
    }
  }
  int steady_ticks = 0;
  for (const int phase_ticks : ticks) steady_ticks += phase_ticks;
  std::printf("expert Act: %ld heap allocations in %d ticks between plans (16 episodes)\n", allocations, steady_ticks);
  // Every phase of a successful pick was exercised: the cue, scan and peek phases, the reach,
  // both kinds of way out (withdraw, lift).
  for (const Phase phase : {Phase::kWatchCue, Phase::kLook, Phase::kSettle, Phase::kPeek, Phase::kApproach,
                            Phase::kDescend, Phase::kClose, Phase::kWithdraw, Phase::kLift}) {
    EXPECT_GT(ticks[static_cast<std::size_t>(phase)], 0) << kPhaseNames[static_cast<std::size_t>(phase)];
  }
}

TEST(PickExpertAllocation, RetreatsAllocateOnlyToPlanAgain) {
  std::array<int, kPhases> ticks{};
  for (const char* robot : {"gr1t2", "reachy2"}) {
    const ActAllocations run = RunEpisode("clutter-pick-cube", robot, 0, GripReading::kClosedOnNothing);
    EXPECT_GE(run.attempts, 2) << robot << ": the expert retried";
    ExpectSteadyTicksAllocateNothing(run, std::string("clutter-pick-cube on ") + robot + ", every grasp missing",
                                     ticks);
  }
  EXPECT_GT(ticks[static_cast<std::size_t>(Phase::kRetreat)], 0);
}

}  // namespace
}  // namespace tavis::scenarios::expert
