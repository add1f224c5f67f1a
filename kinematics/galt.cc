#include "kinematics/galt.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace tavis::kinematics {
namespace {

// The reference needs at least this many samples (spec 11.3 step 1).
constexpr int kMinSteps = 10;

// Python's int(round(x)): round half to even, independent of the floating-point environment.
int RoundHalfEven(double x) {
  const double floor_x = std::floor(x);
  const double fraction = x - floor_x;
  double rounded = floor_x;
  if (fraction > 0.5 || (fraction == 0.5 && std::fmod(floor_x, 2.0) != 0.0)) rounded += 1.0;
  return static_cast<int>(rounded);
}

// GaltParams durations discretised at the sampling rate (spec 11.1).
struct StepCounts {
  int fixation_persistence;  // k_persist
  int min_stable;            // min_stable_steps
  int lookback;
  int slack;
};

StepCounts Discretise(const GaltParams& params, double fps) {
  return {std::max(1, RoundHalfEven(params.k_fix_s * fps)),
          std::max(1, RoundHalfEven(params.min_stable_for_onset_s * fps)), RoundHalfEven(params.lookback_s * fps),
          RoundHalfEven(params.forward_slack_s * fps)};
}

// _velocity (spec 11.2) at one step, without materialising the array: the L2 norm of the forward
// difference times fps, the last step repeating the one before. Squares are summed left to
// right and the square root is taken before scaling, as numpy does.
double SpeedAt(const TrajectoryView& trajectory, const std::array<int, 3>& columns, int step, double fps) {
  const int from = std::min(step, trajectory.num_steps - 2);
  double sum_of_squares = 0.0;
  for (const int column : columns) {
    const double delta = trajectory.at(from + 1, column) - trajectory.at(from, column);
    sum_of_squares += delta * delta;
  }
  return std::sqrt(sum_of_squares) * fps;
}

// _find_gripper_events (spec 11.2): a gripper is "closed" when its command is >= 0; an event is
// the first sample after a change.
bool GripperClosed(const TrajectoryView& trajectory, int column, int step) {
  return trajectory.at(step, column) >= 0.0;
}

bool IsGripperEvent(const TrajectoryView& trajectory, int column, int step) {
  return GripperClosed(trajectory, column, step) != GripperClosed(trajectory, column, step - 1);
}

// The latest gripper event (the reference's anchor, spec 11.3 step b), or -1 if none.
int LastGripperEvent(const TrajectoryView& trajectory, int column) {
  for (int step = trajectory.num_steps - 1; step >= 1; --step) {
    if (IsGripperEvent(trajectory, column, step)) return step;
  }
  return -1;
}

// _backward_search_hand_onset (spec 11.2): walking back from the anchor, the first run of
// min_stable slow steps ends the search; the onset is the step after that run, and the search
// fails (no further runs are considered) when that step is the anchor itself.
std::optional<int> BackwardSearchHandOnset(const TrajectoryView& trajectory, const std::array<int, 3>& ee_columns,
                                           int anchor, double fps, double v_hand_thresh, int min_stable) {
  int stable_run = 0;
  for (int step = anchor - 1; step >= 0; --step) {
    if (SpeedAt(trajectory, ee_columns, step, fps) < v_hand_thresh) {
      if (++stable_run >= min_stable) {
        const int onset = step + stable_run;
        if (onset < anchor) return onset;
        return std::nullopt;
      }
    } else {
      stable_run = 0;
    }
  }
  return std::nullopt;
}

// _find_settled_intervals + the candidate choice of _match_head_arrival (spec 11.2): settled
// interval starts in [window_begin, window_end) are runs of >= k slow neck steps, cut at the
// window edges. The preferred start is the latest one <= anchor, else the earliest after it.
std::optional<int> BestSettledStart(const TrajectoryView& trajectory, const std::array<int, 3>& neck_columns,
                                    int anchor, double fps, double v_sac_thresh, int fixation_persistence,
                                    int window_begin, int window_end) {
  window_begin = std::max(0, window_begin);
  window_end = std::min(trajectory.num_steps, window_end);
  std::optional<int> latest_pre_anchor;
  int run_start = 0;
  int run_length = 0;
  for (int step = window_begin; step < window_end; ++step) {
    if (!(SpeedAt(trajectory, neck_columns, step, fps) < v_sac_thresh)) {
      run_length = 0;
      continue;
    }
    if (run_length == 0) run_start = step;
    if (++run_length != fixation_persistence) continue;
    if (run_start <= anchor) {
      latest_pre_anchor = run_start;
    } else {
      // Starts only grow from here, so this is the earliest post-anchor candidate and no
      // pre-anchor candidate can follow.
      return latest_pre_anchor ? latest_pre_anchor : run_start;
    }
  }
  return latest_pre_anchor;
}

// np.max(np.abs(a - b)) >= margin over the neck joints; a NaN difference makes numpy's maximum
// NaN and the comparison false.
bool NeckFarFrom(const TrajectoryView& trajectory, const std::array<int, 3>& neck_columns, int step, int reference_step,
                 double margin) {
  bool far = false;
  for (const int column : neck_columns) {
    const double distance = std::fabs(trajectory.at(step, column) - trajectory.at(reference_step, column));
    if (std::isnan(distance)) return false;
    far = far || distance >= margin;
  }
  return far;
}

// _refine_arrival_by_position (spec 11.2): the earliest step from which the neck stayed within
// the margin of its settled position; not limited to the search window.
int RefineArrivalByPosition(const TrajectoryView& trajectory, const std::array<int, 3>& neck_columns, int settled_step,
                            double margin) {
  for (int step = settled_step - 1; step >= 0; --step) {
    if (NeckFarFrom(trajectory, neck_columns, step, settled_step, margin)) return step + 1;
  }
  return 0;
}

// How far the single-anchor pipeline (spec 11.3 steps c-f) got for one arm.
struct AnchorOutcome {
  GaltReason reason = GaltReason::kNoGrasp;
  int anchor = -1;
  std::optional<int> hand_onset;
  std::optional<int> head_arrival;

  bool valid() const { return reason == GaltReason::kOk || reason == GaltReason::kOkPostAnchor; }
};

AnchorOutcome EvaluateAnchor(const TrajectoryView& trajectory, const std::array<int, 3>& ee_columns, int anchor,
                             double fps, const GaltParams& params, const ActionLayout& layout,
                             const StepCounts& counts) {
  AnchorOutcome outcome;
  outcome.anchor = anchor;
  outcome.hand_onset =
      BackwardSearchHandOnset(trajectory, ee_columns, anchor, fps, params.v_hand_thresh, counts.min_stable);
  if (!outcome.hand_onset) {
    outcome.reason = GaltReason::kNoHandOnset;
    return outcome;
  }
  // _match_head_arrival: window [anchor - lookback, anchor + slack] inclusive.
  const std::optional<int> settled =
      BestSettledStart(trajectory, layout.neck, anchor, fps, params.v_sac_thresh, counts.fixation_persistence,
                       anchor - counts.lookback, anchor + counts.slack + 1);
  if (!settled) {
    outcome.reason = GaltReason::kNoFixation;
    return outcome;
  }
  const int head_arrival = RefineArrivalByPosition(trajectory, layout.neck, *settled, params.arrival_margin_rad);
  outcome.head_arrival = head_arrival;
  const double galt_s = static_cast<double>(anchor - head_arrival) / fps;
  if (galt_s < params.outlier_min_s) {
    outcome.reason = GaltReason::kOutlierLow;
  } else if (galt_s > params.outlier_max_s) {
    outcome.reason = GaltReason::kOutlierHigh;
  } else {
    // Pre-anchor is decided on the refined time, as in the reference.
    outcome.reason = head_arrival <= anchor ? GaltReason::kOk : GaltReason::kOkPostAnchor;
  }
  return outcome;
}

// Fills the result fields of the outcome that the detector reached; galt_s only when valid.
GaltResult ResultFromOutcome(Side arm, const AnchorOutcome& outcome, double fps) {
  GaltResult result;
  result.reason = outcome.reason;
  result.arm = arm;
  result.t_hand_arrival_s = outcome.anchor / fps;
  if (outcome.hand_onset) {
    result.t_hand_onset_s = *outcome.hand_onset / fps;
    result.arm_reach_s = static_cast<double>(outcome.anchor - *outcome.hand_onset) / fps;
  }
  if (outcome.head_arrival) {
    result.t_head_arrival_s = *outcome.head_arrival / fps;
    if (outcome.valid()) {
      result.galt_s = static_cast<double>(outcome.anchor - *outcome.head_arrival) / fps;
    }
  }
  return result;
}

// Arbitration priority of an invalid arm's reason (spec 11.3 step 4).
int ArbitrationPriority(GaltReason reason) {
  switch (reason) {
    case GaltReason::kNoFixation:
    case GaltReason::kOutlierLow:
    case GaltReason::kOutlierHigh: return 3;
    case GaltReason::kNoHandOnset: return 2;
    case GaltReason::kNoGrasp: return 1;
    default: return 0;
  }
}

GaltResult InvalidResult(GaltReason reason) {
  GaltResult result;
  result.reason = reason;
  return result;
}

struct ArmChannels {
  Side arm;
  const std::array<int, 3>& ee_columns;
  int gripper_column;
};

std::array<ArmChannels, 2> ArmsInReferenceOrder(const ActionLayout& layout) {
  return {ArmChannels{Side::kLeft, layout.left_ee_xyz, layout.left_gripper},
          ArmChannels{Side::kRight, layout.right_ee_xyz, layout.right_gripper}};
}

GaltResult ComputeGaltUnchecked(const TrajectoryView& trajectory, double fps, const GaltParams& params,
                                const ActionLayout& layout) {
  if (trajectory.num_steps < kMinSteps) return InvalidResult(GaltReason::kTooShort);
  const StepCounts counts = Discretise(params, fps);

  std::array<AnchorOutcome, 2> outcomes;
  const std::array<ArmChannels, 2> arms = ArmsInReferenceOrder(layout);
  for (std::size_t i = 0; i < arms.size(); ++i) {
    const int anchor = LastGripperEvent(trajectory, arms[i].gripper_column);
    if (anchor >= 0) {
      outcomes[i] = EvaluateAnchor(trajectory, arms[i].ee_columns, anchor, fps, params, layout, counts);
    }
  }

  const bool left_valid = outcomes[0].valid();
  const bool right_valid = outcomes[1].valid();
  if (left_valid && right_valid) return InvalidResult(GaltReason::kAmbiguousArms);
  if (left_valid) return ResultFromOutcome(Side::kLeft, outcomes[0], fps);
  if (right_valid) return ResultFromOutcome(Side::kRight, outcomes[1], fps);
  // Python's max() keeps the first (left) reason on equal priority.
  const GaltReason left_reason = outcomes[0].reason;
  const GaltReason right_reason = outcomes[1].reason;
  return InvalidResult(ArbitrationPriority(right_reason) > ArbitrationPriority(left_reason) ? right_reason
                                                                                            : left_reason);
}

std::vector<GaltResult> ComputeGaltEventsUnchecked(const TrajectoryView& trajectory, double fps,
                                                   const GaltParams& params, const ActionLayout& layout) {
  if (trajectory.num_steps < kMinSteps) return {InvalidResult(GaltReason::kTooShort)};
  const StepCounts counts = Discretise(params, fps);

  struct Event {
    int step;
    GaltResult result;
  };
  std::vector<Event> events;
  for (const ArmChannels& arm : ArmsInReferenceOrder(layout)) {
    for (int step = 1; step < trajectory.num_steps; ++step) {
      if (!IsGripperEvent(trajectory, arm.gripper_column, step)) continue;
      const AnchorOutcome outcome = EvaluateAnchor(trajectory, arm.ee_columns, step, fps, params, layout, counts);
      events.push_back({step, ResultFromOutcome(arm.arm, outcome, fps)});
    }
  }
  if (events.empty()) return {InvalidResult(GaltReason::kNoGrasp)};

  // Left-arm events were appended first, so a stable sort keeps them first on equal steps.
  std::stable_sort(events.begin(), events.end(), [](const Event& a, const Event& b) { return a.step < b.step; });
  std::vector<GaltResult> results;
  results.reserve(events.size());
  for (Event& event : events) results.push_back(std::move(event.result));
  return results;
}

void ValidateBatch(const std::vector<TrajectoryView>& episodes, double fps, const ActionLayout& layout) {
  for (std::size_t i = 0; i < episodes.size(); ++i) {
    try {
      ValidateGaltInput(episodes[i], fps, layout);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("episode " + std::to_string(i) + ": " + e.what());
    }
  }
}

// Runs compute(i) for every episode index in parallel; each writes only its own slot.
template <typename Compute>
void ForEachEpisodeParallel(std::size_t count, const Compute& compute) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) compute(i);
  });
}

}  // namespace

bool ParseGaltReason(const std::string& text, GaltReason* reason) {
  for (int r = 0; r < kGaltReasonCount; ++r) {
    if (text == ToString(static_cast<GaltReason>(r))) {
      *reason = static_cast<GaltReason>(r);
      return true;
    }
  }
  return false;
}

const char* ToString(GaltReason reason) {
  switch (reason) {
    case GaltReason::kOk: return "ok";
    case GaltReason::kOkPostAnchor: return "ok_post_anchor";
    case GaltReason::kNoGrasp: return "no_grasp";
    case GaltReason::kNoHandOnset: return "no_hand_onset";
    case GaltReason::kNoFixation: return "no_fixation";
    case GaltReason::kOutlierLow: return "outlier_low";
    case GaltReason::kOutlierHigh: return "outlier_high";
    case GaltReason::kAmbiguousArms: return "ambiguous_arms";
    case GaltReason::kTooShort: return "too_short";
  }
  return "unknown";
}

void ValidateGaltInput(const TrajectoryView& trajectory, double fps, const ActionLayout& layout) {
  if (!(fps > 0.0) || !std::isfinite(fps)) {
    throw std::invalid_argument("GALT: fps must be a positive number, got " + std::to_string(fps));
  }
  if (trajectory.num_steps < 0 || trajectory.row_stride <= 0 ||
      (trajectory.num_steps > 0 && trajectory.data == nullptr)) {
    throw std::invalid_argument("GALT: malformed trajectory view (" + std::to_string(trajectory.num_steps) +
                                " steps, row stride " + std::to_string(trajectory.row_stride) + ")");
  }
  const auto check_column = [&](int column, const char* channel) {
    if (column < 0 || column >= trajectory.row_stride) {
      throw std::invalid_argument(std::string("GALT: layout column ") + channel + " = " + std::to_string(column) +
                                  " is outside a row of " + std::to_string(trajectory.row_stride) + " values");
    }
  };
  for (const int column : layout.left_ee_xyz) check_column(column, "left_ee_xyz");
  for (const int column : layout.right_ee_xyz) check_column(column, "right_ee_xyz");
  for (const int column : layout.neck) check_column(column, "neck");
  check_column(layout.left_gripper, "left_gripper");
  check_column(layout.right_gripper, "right_gripper");
}

GaltResult ComputeGalt(const TrajectoryView& trajectory, double fps, const GaltParams& params,
                       const ActionLayout& layout) {
  ValidateGaltInput(trajectory, fps, layout);
  return ComputeGaltUnchecked(trajectory, fps, params, layout);
}

std::vector<GaltResult> ComputeGaltEvents(const TrajectoryView& trajectory, double fps, const GaltParams& params,
                                          const ActionLayout& layout) {
  ValidateGaltInput(trajectory, fps, layout);
  return ComputeGaltEventsUnchecked(trajectory, fps, params, layout);
}

std::vector<GaltResult> ComputeGaltBatch(const std::vector<TrajectoryView>& episodes, double fps,
                                         const GaltParams& params, const ActionLayout& layout) {
  ValidateBatch(episodes, fps, layout);
  std::vector<GaltResult> results(episodes.size());
  ForEachEpisodeParallel(episodes.size(),
                         [&](std::size_t i) { results[i] = ComputeGaltUnchecked(episodes[i], fps, params, layout); });
  return results;
}

std::vector<std::vector<GaltResult>> ComputeGaltEventsBatch(const std::vector<TrajectoryView>& episodes, double fps,
                                                            const GaltParams& params, const ActionLayout& layout) {
  ValidateBatch(episodes, fps, layout);
  std::vector<std::vector<GaltResult>> results(episodes.size());
  ForEachEpisodeParallel(episodes.size(), [&](std::size_t i) {
    results[i] = ComputeGaltEventsUnchecked(episodes[i], fps, params, layout);
  });
  return results;
}

}  // namespace tavis::kinematics
