// Where a cell's time goes: the summed time of each stage (actions/IK, physics, neck, task,
// end checks, reset, render, policy, recording, the driver's own serial work), every episode's
// measured cost, and from those costs the cell's critical path: the time it would take with
// unlimited threads. CellProfiler collects it (an episode loop observer); `tavis eval
// --profile` prints it and writes DIR/profile.json.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "kinematics/cpu_clock.h"

namespace tavis::batch::cell {

using kinematics::ProcessCpuNanoseconds;
using kinematics::ThreadCpuNanoseconds;

struct EpisodeCost {
  int64_t episode = 0;
  int slot = 0;
  int64_t control_ticks = 0;
  double seconds = 0.0;  // CPU time of its env's reset and ticks and of the policy's work for it
};

struct CellProfile {
  // Run on the driver's per-slot schedule (each episode on one thread from start to end, the
  // next dealt as a thread frees up) rather than lock-step (a section per tick across the batch).
  bool per_slot = false;
  // (name, seconds) per stage, summed over envs and threads: the env's stages, then "render"
  // (the CPU time spent in render calls), lock-step "render_idle" (the thread time batch render
  // calls held without rendering: each holds every thread until its last tile is done),
  // "policy", "recording" (the sinks) and "driver" (the rest of the serial loop).
  std::vector<std::pair<std::string, double>> stages;
  std::vector<EpisodeCost> episodes;  // in the order they ended
  int threads = 1;
  double wall_seconds = 0.0;
  // Wall time outside the parallel sections (collecting, refilling, sinks, the tick loop).
  double serial_seconds = 0.0;
  // Per parallel section (a refill's resets, a tick's policy and step), the slowest env's cost,
  // summed: the parallel sections' part of the critical path.
  double slowest_env_seconds = 0.0;
  // Per section, max(slowest env, section work / threads) summed, for the estimates.
  std::vector<std::pair<double, double>> sections;  // (slowest env, work)
  // Lock-step: the render calls' wall time x threads, for the estimates (per slot, renders are
  // part of their episodes' costs: 0).
  double render_seconds = 0.0;
  // Render calls' wall time, summed over the calling threads (per slot, with the time helping
  // threads spent on their tiles).
  double render_wall_seconds = 0.0;
  double render_cpu_seconds = 0.0;  // CPU time inside render calls (every thread's)
  // Thread time render calls held without rendering: lock-step, the "render_idle" stage; per
  // slot, a call's wall time beyond its thread's CPU time (the machine preempting it, or the
  // thread waiting for the last tiles a helping thread took).
  double render_idle_seconds = 0.0;

  double work_seconds() const;  // all measured work (stages' sum)
  // The time with unlimited threads: serial time plus, lock-step, the slowest env of every
  // section; per slot, the longest episode.
  double critical_path_seconds() const;
  // The cell's time on `threads` threads estimated from the measured costs. Lock-step: serial
  // time plus, per section, the longer of its slowest env and its work spread over the threads.
  // Per slot: serial time plus the span of the episodes dealt in index order, each to the thread
  // that frees up first.
  double EstimatedSeconds(int threads) const;
};

// A text table: stage shares, episode costs, critical path and the 1/2/16-thread estimates.
std::string FormatCellProfile(const CellProfile& profile);
// The same as JSON, with every episode's cost.
std::string CellProfileJson(const CellProfile& profile);

}  // namespace tavis::batch::cell
