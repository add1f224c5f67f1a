// GALT (Gaze-Action Lead Time): how long before a gripper event the head arrived at its final
// fixation, measured on a commanded-action trajectory alone (no simulator state).
//
// An exact port of the reference detector, tavis/eval/galt.py (reference spec section 11):
// same parameters, same integer discretisation, same strict/non-strict comparisons, same reason
// codes and arm arbitration, so that every result agrees with the reference to the last bit of
// the step indices. The reference's per-arm debug dictionary is not reproduced.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "kinematics/action.h"

namespace tavis::kinematics {

// GaltParams of the reference (spec 11.1); durations in seconds, speeds in m/s or rad/s.
struct GaltParams {
  double v_hand_thresh = 0.05;            // commanded end-effector linear speed floor (m/s)
  double v_sac_thresh = 0.10;             // commanded neck joint speed floor (rad/s)
  double k_fix_s = 0.080;                 // fixation persistence: shortest settled interval
  double min_stable_for_onset_s = 0.300;  // hand rest needed before the reach onset
  double lookback_s = 3.0;                // head-arrival window before the anchor
  double forward_slack_s = 0.5;           // head-arrival window after the anchor
  double outlier_min_s = -0.5;            // GALT below this is outlier_low (strict)
  double outlier_max_s = 4.0;             // GALT above this is outlier_high (strict)
  double arrival_margin_rad = 0.05;       // L-inf neck tolerance of the position refinement
};

// Column indices of the channels GALT reads (spec 11.1, ActionLayout); quaternions are ignored.
// The defaults are the canonical action's (spec 5).
struct ActionLayout {
  std::array<int, 3> left_ee_xyz{action::kArmPosition[0], action::kArmPosition[0] + 1, action::kArmPosition[0] + 2};
  std::array<int, 3> right_ee_xyz{action::kArmPosition[1], action::kArmPosition[1] + 1, action::kArmPosition[1] + 2};
  std::array<int, 3> neck{action::kNeckRoll, action::kNeckPitch, action::kNeckYaw};
  int left_gripper = action::kGripper[0];
  int right_gripper = action::kGripper[1];
};

// A read-only, row-major trajectory: step t, column j is data[t * row_stride + j].
struct TrajectoryView {
  const double* data = nullptr;
  int num_steps = 0;
  int row_stride = action::kSize;

  double at(int step, int column) const { return data[static_cast<std::ptrdiff_t>(step) * row_stride + column]; }

  // Every `stride`-th step starting at step 0 (a 60 Hz trajectory seen at 20 Hz with stride 3),
  // without copying.
  TrajectoryView Downsampled(int stride) const {
    return {data, (num_steps + stride - 1) / stride, row_stride * stride};
  }
};

// Reason codes (spec 11.3); ToString gives the reference's strings.
enum class GaltReason {
  kOk,             // valid, head arrived before (or at) the gripper event
  kOkPostAnchor,   // valid, but the head arrived after the gripper event
  kNoGrasp,        // no gripper state change
  kNoHandOnset,    // no hand rest-to-motion transition before the gripper event
  kNoFixation,     // no head settling in the search window
  kOutlierLow,     // GALT < outlier_min_s
  kOutlierHigh,    // GALT > outlier_max_s
  kAmbiguousArms,  // both arms gave a valid GALT
  kTooShort,       // fewer than 10 steps
};
inline constexpr int kGaltReasonCount = 9;
const char* ToString(GaltReason reason);
// The reason named `text` (as ToString writes it); false for another text.
bool ParseGaltReason(const std::string& text, GaltReason* reason);

// Times are seconds from the first sample; absent values are nullopt (None in the reference).
struct GaltResult {
  std::optional<double> galt_s;
  GaltReason reason = GaltReason::kNoGrasp;
  std::optional<Side> arm;  // Name(Side) gives the reference's "left" / "right"
  std::optional<double> t_head_arrival_s;
  std::optional<double> t_hand_arrival_s;  // the gripper event itself (spec 13 #12)
  std::optional<double> t_hand_onset_s;
  std::optional<double> arm_reach_s;  // t_hand_arrival_s - t_hand_onset_s
};

// Throws std::invalid_argument unless fps > 0 and every layout column lies in [0, row_stride).
void ValidateGaltInput(const TrajectoryView& trajectory, double fps, const ActionLayout& layout);

// The reference compute_galt: the latest gripper event of each arm is the anchor, then arm
// arbitration. Allocation-free.
GaltResult ComputeGalt(const TrajectoryView& trajectory, double fps, const GaltParams& params = {},
                       const ActionLayout& layout = {});

// Multi-event mode (an extension; the reference evaluates only the latest event): one result per
// gripper event of each arm, ordered by event step, left arm first on equal steps. Each result
// has `arm` and `t_hand_arrival_s` (the event) set; the other fields follow the single-event
// rules for that anchor, with reasons ok, ok_post_anchor, no_hand_onset, no_fixation,
// outlier_low or outlier_high (no arbitration between arms). A trajectory without events
// yields a single result with reason no_grasp (or too_short).
std::vector<GaltResult> ComputeGaltEvents(const TrajectoryView& trajectory, double fps, const GaltParams& params = {},
                                          const ActionLayout& layout = {});

// ComputeGalt for every episode, in parallel over episodes; results[i] belongs to episodes[i]
// and does not depend on the number of threads. Validates all inputs before starting.
std::vector<GaltResult> ComputeGaltBatch(const std::vector<TrajectoryView>& episodes, double fps,
                                         const GaltParams& params = {}, const ActionLayout& layout = {});

// ComputeGaltEvents for every episode, in parallel over episodes.
std::vector<std::vector<GaltResult>> ComputeGaltEventsBatch(const std::vector<TrajectoryView>& episodes, double fps,
                                                            const GaltParams& params = {},
                                                            const ActionLayout& layout = {});

}  // namespace tavis::kinematics
