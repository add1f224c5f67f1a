#include "kinematics/galt.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tavis::kinematics {
namespace {

// A subset of the reference vectors kept in the repository (tests/data/galt/README.md), so that
// a clone alone passes.
const std::string kConformanceDir = std::string(TAVIS_REPO_TEST_DATA_DIR) + "/galt/";

// A T x 19 trajectory stored row-major.
struct Trajectory {
  std::vector<double> values;
  int num_steps = 0;

  TrajectoryView view() const { return {values.data(), num_steps, action::kSize}; }
  double& at(int step, int column) { return values[static_cast<std::size_t>(step) * action::kSize + column]; }
};

// The conformance CSVs are plain: no header, 19 numbers per row.
Trajectory LoadConformanceCsv(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << path;
  Trajectory trajectory;
  std::string line;
  while (std::getline(in, line)) {
    std::stringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) trajectory.values.push_back(std::stod(field));
    ++trajectory.num_steps;
  }
  EXPECT_EQ(trajectory.values.size(), static_cast<std::size_t>(trajectory.num_steps) * action::kSize) << path;
  return trajectory;
}

struct ConformanceCase {
  std::string file;
  double fps = 0.0;
  nlohmann::json expected;
  Trajectory trajectory;
};

std::vector<ConformanceCase> LoadConformanceCases() {
  std::ifstream in(kConformanceDir + "expected.jsonl");
  EXPECT_TRUE(in) << kConformanceDir;
  std::vector<ConformanceCase> cases;
  std::string line;
  while (std::getline(in, line)) {
    ConformanceCase c;
    c.expected = nlohmann::json::parse(line);
    c.file = c.expected.at("file").get<std::string>();
    c.fps = c.expected.at("fps").get<double>();
    c.trajectory = LoadConformanceCsv(kConformanceDir + c.file);
    cases.push_back(std::move(c));
  }
  return cases;
}

// Empty when `actual` matches the reference's JSON record, else what differs.
std::string Mismatch(const GaltResult& actual, const nlohmann::json& expected) {
  std::ostringstream out;
  if (ToString(actual.reason) != expected.at("reason").get<std::string>()) {
    out << " reason " << ToString(actual.reason) << " != " << expected.at("reason");
  }
  const std::string arm = actual.arm ? Name(*actual.arm) : "null";
  const std::string expected_arm = expected.at("arm").is_null() ? "null" : expected.at("arm").get<std::string>();
  if (arm != expected_arm) out << " arm " << arm << " != " << expected_arm;
  const std::pair<const char*, const std::optional<double>*> times[] = {{"galt_s", &actual.galt_s},
                                                                        {"t_head_arrival_s", &actual.t_head_arrival_s},
                                                                        {"t_hand_arrival_s", &actual.t_hand_arrival_s},
                                                                        {"t_hand_onset_s", &actual.t_hand_onset_s},
                                                                        {"arm_reach_s", &actual.arm_reach_s}};
  for (const auto& [key, value] : times) {
    const nlohmann::json& want = expected.at(key);
    const bool agree =
        want.is_null() ? !value->has_value() : value->has_value() && std::abs(**value - want.get<double>()) <= 1e-9;
    if (!agree) {
      out << " " << key << " " << (value->has_value() ? std::to_string(**value) : "null") << " != " << want;
    }
  }
  return out.str();
}

TEST(GaltConformance, AllReferenceVectorsAgree) {
  const std::vector<ConformanceCase> cases = LoadConformanceCases();
  ASSERT_EQ(cases.size(), 36u);
  int agreeing = 0;
  for (const ConformanceCase& c : cases) {
    const std::string mismatch = Mismatch(ComputeGalt(c.trajectory.view(), c.fps), c.expected);
    if (mismatch.empty()) {
      ++agreeing;
    } else {
      ADD_FAILURE() << c.file << ":" << mismatch;
    }
  }
  std::cout << "[ conformance ] " << agreeing << " of " << cases.size() << " vectors agree\n";
  EXPECT_EQ(agreeing, static_cast<int>(cases.size()));
}

TEST(GaltBatch, EqualsPerEpisodeResultsWithOneAndTwoThreads) {
  const std::vector<ConformanceCase> cases = LoadConformanceCases();
  // The batch API takes one fps; run it on the cases of each rate.
  for (const double fps : {20.0, 30.0, 60.0}) {
    std::vector<TrajectoryView> views;
    std::vector<GaltResult> expected;
    for (const ConformanceCase& c : cases) {
      if (c.fps != fps) continue;
      views.push_back(c.trajectory.view());
      expected.push_back(ComputeGalt(c.trajectory.view(), fps));
    }
    ASSERT_GT(views.size(), 10u) << fps;
    for (const std::size_t threads : {1u, 2u}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      const std::vector<GaltResult> batch = ComputeGaltBatch(views, fps);
      ASSERT_EQ(batch.size(), expected.size());
      for (std::size_t i = 0; i < batch.size(); ++i) {
        EXPECT_EQ(batch[i].reason, expected[i].reason) << "fps " << fps << " episode " << i;
        EXPECT_EQ(batch[i].arm, expected[i].arm);
        EXPECT_EQ(batch[i].galt_s, expected[i].galt_s);
        EXPECT_EQ(batch[i].t_head_arrival_s, expected[i].t_head_arrival_s);
        EXPECT_EQ(batch[i].t_hand_onset_s, expected[i].t_hand_onset_s);
      }
      const std::vector<std::vector<GaltResult>> events = ComputeGaltEventsBatch(views, fps);
      ASSERT_EQ(events.size(), views.size());
      for (std::size_t i = 0; i < events.size(); ++i) {
        EXPECT_EQ(events[i].size(), ComputeGaltEvents(views[i], fps).size());
      }
    }
  }
}

// Builds synthetic trajectories: everything zero, grippers open (-1), edited per test.
class EpisodeBuilder {
 public:
  explicit EpisodeBuilder(int num_steps) {
    trajectory_.num_steps = num_steps;
    trajectory_.values.assign(static_cast<std::size_t>(num_steps) * action::kSize, 0.0);
    for (int t = 0; t < num_steps; ++t) {
      trajectory_.at(t, action::kGripper[0]) = -1.0;
      trajectory_.at(t, action::kGripper[1]) = -1.0;
    }
  }

  // Linear ramp of `column` from `from` at step `begin` to `to` at step `end`, held after.
  // Values are from + k * increment, exact when the increment is a power of two.
  EpisodeBuilder& Ramp(int column, int begin, int end, double from, double to) {
    const double increment = (to - from) / (end - begin);
    for (int t = begin; t < trajectory_.num_steps; ++t) {
      trajectory_.at(t, column) = t >= end ? to : from + (t - begin) * increment;
    }
    return *this;
  }

  // Sets the gripper to `value` from `step` on.
  EpisodeBuilder& Gripper(Side side, int step, double value) {
    for (int t = step; t < trajectory_.num_steps; ++t) {
      trajectory_.at(t, action::kGripper[Index(side)]) = value;
    }
    return *this;
  }

  // A reach: the hand rests, moves along x from `onset` to `grasp`, the gripper closes at grasp.
  EpisodeBuilder& Reach(Side side, int onset, int grasp) {
    Ramp(action::kArmPosition[Index(side)], onset, grasp, 0.0, 0.5);
    return Gripper(side, grasp, 1.0);
  }

  Trajectory trajectory() const { return trajectory_; }

 private:
  Trajectory trajectory_;
};

// The reference's own self-test (spec 11.3, galt.py _synth_episode): 300 steps at 60 Hz, the
// neck pitch ramps to 0.8 over the first second, the right hand moves from 1.4 s to 2.0 s and its
// gripper closes at 2.0 s. Values are float32 as in the reference.
TEST(Galt, ReferenceSelfTest) {
  const double fps = 60.0;
  Trajectory episode = EpisodeBuilder(300).trajectory();
  const int head_samples = 60;  // t < 1.0 s
  const int reach_begin = 84;   // 1.4 s
  const int grasp = 120;        // 2.0 s
  const double target[3] = {0.5, -0.2, 0.3};
  for (int t = 0; t < episode.num_steps; ++t) {
    const double pitch = t < head_samples ? 0.8 * t / (head_samples - 1) : 0.8;
    episode.at(t, action::kNeckPitch) = static_cast<float>(pitch);
    // np.linspace(0, 1, 36) over steps 84..119, then the target.
    double reach = t < grasp ? 0.0 : 1.0;
    if (t >= reach_begin && t < grasp) {
      reach = static_cast<double>(t - reach_begin) / (grasp - 1 - reach_begin);
    }
    for (int axis = 0; axis < 3; ++axis) {
      episode.at(t, action::kArmPosition[1] + axis) = static_cast<float>(reach * target[axis]);
    }
    episode.at(t, action::kGripper[1]) = t >= grasp ? 1.0 : -1.0;
  }
  const GaltResult result = ComputeGalt(episode.view(), fps);
  EXPECT_EQ(result.reason, GaltReason::kOk);
  ASSERT_TRUE(result.arm.has_value());
  EXPECT_EQ(*result.arm, Side::kRight);
  ASSERT_TRUE(result.galt_s.has_value());
  EXPECT_NEAR(*result.galt_s, 1.0, 0.1);
  std::cout << "[ self-test ] reason " << ToString(result.reason) << ", arm " << Name(*result.arm) << ", GALT "
            << *result.galt_s << " s\n";
}

TEST(Galt, FewerThanTenStepsIsTooShort) {
  const Trajectory nine = EpisodeBuilder(9).Reach(Side::kRight, 2, 5).trajectory();
  const GaltResult result = ComputeGalt(nine.view(), 20.0);
  EXPECT_EQ(result.reason, GaltReason::kTooShort);
  EXPECT_FALSE(result.galt_s.has_value());
  EXPECT_FALSE(result.arm.has_value());
  const Trajectory ten = EpisodeBuilder(10).trajectory();
  EXPECT_EQ(ComputeGalt(ten.view(), 20.0).reason, GaltReason::kNoGrasp);
}

// At 20 Hz: head settles at step 20, the hand rests, reaches from step 40, grasps at step 60.
EpisodeBuilder LookThenReach(Side side, int num_steps = 100) {
  EpisodeBuilder builder(num_steps);
  builder.Ramp(action::kNeckYaw, 0, 20, 0.0, 0.6).Reach(side, 40, 60);
  return builder;
}

TEST(Galt, LookThenReachIsValid) {
  const GaltResult result = ComputeGalt(LookThenReach(Side::kLeft).trajectory().view(), 20.0);
  EXPECT_EQ(result.reason, GaltReason::kOk);
  EXPECT_EQ(result.arm, Side::kLeft);
  // Settled from step 20; the position refinement moves the arrival to step 19, the last ramp
  // step, which is 0.03 rad from the final position (within the 0.05 rad margin).
  EXPECT_DOUBLE_EQ(*result.t_head_arrival_s, 19 / 20.0);
  EXPECT_DOUBLE_EQ(*result.t_hand_arrival_s, 60 / 20.0);
  EXPECT_DOUBLE_EQ(*result.t_hand_onset_s, 40 / 20.0);
  EXPECT_DOUBLE_EQ(*result.arm_reach_s, 20 / 20.0);
  EXPECT_DOUBLE_EQ(*result.galt_s, (60 - 19) / 20.0);
}

TEST(Galt, BothArmsValidIsAmbiguous) {
  EpisodeBuilder builder = LookThenReach(Side::kLeft);
  builder.Reach(Side::kRight, 45, 65);
  const GaltResult result = ComputeGalt(builder.trajectory().view(), 20.0);
  EXPECT_EQ(result.reason, GaltReason::kAmbiguousArms);
  EXPECT_FALSE(result.galt_s.has_value());
  EXPECT_FALSE(result.arm.has_value());
}

TEST(Galt, HandRestingRightUpToTheGraspHasNoOnset) {
  // The gripper closes while the hand has been still for the whole episode.
  const Trajectory episode =
      EpisodeBuilder(100).Ramp(action::kNeckYaw, 0, 20, 0.0, 0.6).Gripper(Side::kRight, 60, 1.0).trajectory();
  EXPECT_EQ(ComputeGalt(episode.view(), 20.0).reason, GaltReason::kNoHandOnset);
}

TEST(Galt, InvalidArmsTakeTheHigherPriorityReason) {
  // Left: grasp without a reach (no_hand_onset, priority 2); right: nothing (no_grasp, 1).
  Trajectory episode = EpisodeBuilder(100).Gripper(Side::kLeft, 60, 1.0).trajectory();
  EXPECT_EQ(ComputeGalt(episode.view(), 20.0).reason, GaltReason::kNoHandOnset);
  // Right instead of left: the right arm's reason wins by priority, not by order.
  episode = EpisodeBuilder(100).Gripper(Side::kRight, 60, 1.0).trajectory();
  EXPECT_EQ(ComputeGalt(episode.view(), 20.0).reason, GaltReason::kNoHandOnset);
}

TEST(Galt, EqualPriorityReasonsKeepTheLeftArms) {
  // The head settles at step 20 and sweeps from step 130 on. A grasp at 120 sees the fixation
  // 5 s earlier (outlier_high); a grasp at 250 sees no settling (no_fixation); both priority 3.
  for (const Side late_arm : {Side::kLeft, Side::kRight}) {
    const Side early_arm = late_arm == Side::kLeft ? Side::kRight : Side::kLeft;
    const Trajectory episode = EpisodeBuilder(300)
                                   .Ramp(action::kNeckYaw, 0, 20, 0.0, 0.6)
                                   .Ramp(action::kNeckYaw, 130, 300, 0.6, 17.6)
                                   .Reach(early_arm, 100, 120)
                                   .Reach(late_arm, 230, 250)
                                   .trajectory();
    EXPECT_EQ(ComputeGalt(episode.view(), 20.0).reason,
              late_arm == Side::kLeft ? GaltReason::kNoFixation : GaltReason::kOutlierHigh);
  }
}

TEST(Galt, SearchWindowCutsSettledRuns) {
  // Fast turn until step 10, then a slow drift (0.08 rad/s, below v_sac_thresh) to the end: one
  // settled run from step 10. The window of the grasp at 100 starts at 40, so the candidate is
  // 40, refined back while within 0.05 rad: 0.004 rad/step * 12 steps -> arrival at step 28.
  const Trajectory episode = EpisodeBuilder(120)
                                 .Ramp(action::kNeckYaw, 0, 10, 0.0, 1.0)
                                 .Ramp(action::kNeckYaw, 10, 120, 1.0, 1.44)
                                 .Reach(Side::kRight, 80, 100)
                                 .trajectory();
  const GaltResult result = ComputeGalt(episode.view(), 20.0);
  EXPECT_EQ(result.reason, GaltReason::kOk);
  EXPECT_DOUBLE_EQ(*result.t_head_arrival_s, 28 / 20.0);
}

TEST(Galt, ComparisonsAtThresholdsFollowTheReference) {
  // Power-of-two steps at 16 Hz make the quantities hit the thresholds exactly.
  const double fps = 16.0;
  // Neck 0.125 rad/step until step 20. Refinement stops where the distance reaches the margin
  // (>=): 0.25 rad at step 18, so the arrival is step 19.
  EpisodeBuilder builder(120);
  builder.Ramp(action::kNeckYaw, 0, 20, 0.0, 2.5).Reach(Side::kRight, 60, 80);
  GaltParams params;
  params.arrival_margin_rad = 0.25;
  EXPECT_DOUBLE_EQ(*ComputeGalt(builder.trajectory().view(), fps, params).t_head_arrival_s, 19 / fps);
  // Default margin: arrival at step 20. GALT exactly outlier_max_s (4 s = 64 steps) is valid,
  // one step more is outlier_high.
  EXPECT_EQ(
      ComputeGalt(
          EpisodeBuilder(120).Ramp(action::kNeckYaw, 0, 20, 0.0, 2.5).Reach(Side::kRight, 60, 84).trajectory().view(),
          fps)
          .galt_s,
      4.0);
  EXPECT_EQ(
      ComputeGalt(
          EpisodeBuilder(120).Ramp(action::kNeckYaw, 0, 20, 0.0, 2.5).Reach(Side::kRight, 60, 85).trajectory().view(),
          fps)
          .reason,
      GaltReason::kOutlierHigh);
  // A hand moving at exactly v_hand_thresh is not at rest (<): 1/32 m per step at 16 Hz is
  // 0.5 m/s. The rest before step 30 gives the onset; were the movement counted as rest, the
  // rest would end at the grasp and there would be no onset.
  params = GaltParams{};
  params.v_hand_thresh = 0.5;
  const Trajectory threshold_reach = EpisodeBuilder(120)
                                         .Ramp(action::kNeckYaw, 0, 20, 0.0, 2.5)
                                         .Ramp(action::kArmPosition[1], 30, 60, 0.0, 0.9375)
                                         .Gripper(Side::kRight, 60, 1.0)
                                         .trajectory();
  const GaltResult result = ComputeGalt(threshold_reach.view(), fps, params);
  EXPECT_EQ(result.reason, GaltReason::kOk);
  EXPECT_EQ(result.t_hand_onset_s, 30 / fps);
}

TEST(Galt, LastSpeedRepeatsTheOneBefore) {
  // _velocity pads the end with the last forward difference: a neck sweeping up to the last
  // step never settles there, even with one-step fixations (0.01 s * 20 Hz rounds to 0, which
  // is clamped to 1 step).
  GaltParams params;
  params.k_fix_s = 0.01;
  const Trajectory episode =
      EpisodeBuilder(70).Ramp(action::kNeckYaw, 0, 70, 0.0, 7.0).Reach(Side::kRight, 40, 65).trajectory();
  EXPECT_EQ(ComputeGalt(episode.view(), 20.0, params).reason, GaltReason::kNoFixation);
}

TEST(Galt, HeadStillMovingIsNoFixation) {
  // The neck sweeps continuously at 2 rad/s, never slower than v_sac_thresh.
  const Trajectory episode =
      EpisodeBuilder(100).Ramp(action::kNeckYaw, 0, 100, 0.0, 9.9).Reach(Side::kRight, 40, 60).trajectory();
  EXPECT_EQ(ComputeGalt(episode.view(), 20.0).reason, GaltReason::kNoFixation);
}

TEST(Galt, PersistenceStepsRoundHalfToEven) {
  // The neck pauses for exactly two steps before the grasp and sweeps otherwise. With
  // k_fix_s * fps = 2.5 the reference rounds to 2 (half to even), so the pause is a fixation;
  // rounding half up would need three slow steps.
  EpisodeBuilder builder(100);
  builder.Ramp(action::kNeckYaw, 0, 30, 0.0, 3.0).Ramp(action::kNeckYaw, 32, 100, 3.0, 9.8);
  builder.Reach(Side::kRight, 40, 60);
  GaltParams params;
  params.k_fix_s = 0.125;  // 2.5 steps at 20 Hz
  const GaltResult half = ComputeGalt(builder.trajectory().view(), 20.0, params);
  EXPECT_EQ(half.reason, GaltReason::kOk);
  EXPECT_DOUBLE_EQ(*half.t_head_arrival_s, 30 / 20.0);
  params.k_fix_s = 0.15;  // 3 steps
  EXPECT_EQ(ComputeGalt(builder.trajectory().view(), 20.0, params).reason, GaltReason::kNoFixation);
}

TEST(Galt, LateHeadArrivalIsOutlierAndPostAnchorIsFlagged) {
  // Head settles 1 s after the grasp, outside the 0.5 s forward slack: no fixation.
  EpisodeBuilder late(140);
  late.Ramp(action::kNeckYaw, 0, 80, 0.0, 8.0).Reach(Side::kRight, 40, 60);
  EXPECT_EQ(ComputeGalt(late.trajectory().view(), 20.0).reason, GaltReason::kNoFixation);
  // Head settles 0.25 s after the grasp, inside the slack: valid but post-anchor.
  EpisodeBuilder post(140);
  post.Ramp(action::kNeckYaw, 0, 65, 0.0, 6.5).Reach(Side::kRight, 40, 60);
  const GaltResult result = ComputeGalt(post.trajectory().view(), 20.0);
  EXPECT_EQ(result.reason, GaltReason::kOkPostAnchor);
  EXPECT_LT(*result.galt_s, 0.0);
  // Head settled 5 s before the grasp and never moved again: GALT > 4 s is outlier_high.
  EpisodeBuilder early(200);
  early.Ramp(action::kNeckYaw, 0, 20, 0.0, 2.0).Reach(Side::kRight, 100, 120);
  EXPECT_EQ(ComputeGalt(early.trajectory().view(), 20.0).reason, GaltReason::kOutlierHigh);
}

TEST(GaltEvents, OneResultPerGripperEventInTimeOrder) {
  // Right arm grasps at 60 and releases at 90 after a pause; left arm grasps at 75.
  EpisodeBuilder builder = LookThenReach(Side::kRight);
  builder.Gripper(Side::kRight, 90, -1.0).Reach(Side::kLeft, 62, 75);
  const Trajectory episode = builder.trajectory();
  const std::vector<GaltResult> events = ComputeGaltEvents(episode.view(), 20.0);
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0].arm, Side::kRight);
  EXPECT_DOUBLE_EQ(*events[0].t_hand_arrival_s, 60 / 20.0);
  EXPECT_EQ(events[0].reason, GaltReason::kOk);
  EXPECT_DOUBLE_EQ(*events[0].galt_s, (60 - 19) / 20.0);
  EXPECT_EQ(events[1].arm, Side::kLeft);
  EXPECT_DOUBLE_EQ(*events[1].t_hand_arrival_s, 75 / 20.0);
  EXPECT_EQ(events[1].reason, GaltReason::kOk);
  EXPECT_DOUBLE_EQ(*events[1].galt_s, (75 - 19) / 20.0);
  EXPECT_EQ(events[2].arm, Side::kRight);
  EXPECT_DOUBLE_EQ(*events[2].t_hand_arrival_s, 90 / 20.0);
  // The release follows a still hand: no onset, and no GALT for it.
  EXPECT_EQ(events[2].reason, GaltReason::kNoHandOnset);
  EXPECT_FALSE(events[2].galt_s.has_value());
}

TEST(GaltEvents, LastEventIsTheReferenceResult) {
  // Right arm: grasp at 60, release at 70, then the head turns to a new fixation (settled at
  // 80) while the hand reaches again from 80 and grasps at 100.
  EpisodeBuilder builder = LookThenReach(Side::kRight, 140);
  builder.Gripper(Side::kRight, 70, -1.0)
      .Ramp(action::kArmPosition[1], 80, 100, 0.5, 0.9)
      .Gripper(Side::kRight, 100, 1.0)
      .Ramp(action::kNeckYaw, 70, 80, 0.6, 1.2);
  const Trajectory episode = builder.trajectory();
  const std::vector<GaltResult> events = ComputeGaltEvents(episode.view(), 20.0);
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0].reason, GaltReason::kOk);
  EXPECT_DOUBLE_EQ(*events[0].galt_s, (60 - 19) / 20.0);
  EXPECT_EQ(events[1].reason, GaltReason::kNoHandOnset);
  EXPECT_EQ(events[2].reason, GaltReason::kOk);
  EXPECT_DOUBLE_EQ(*events[2].galt_s, (100 - 80) / 20.0);

  const GaltResult single = ComputeGalt(episode.view(), 20.0);
  EXPECT_EQ(single.reason, GaltReason::kOk);
  EXPECT_EQ(single.arm, Side::kRight);
  EXPECT_EQ(single.galt_s, events[2].galt_s);
  EXPECT_EQ(single.t_head_arrival_s, events[2].t_head_arrival_s);
  EXPECT_EQ(single.t_hand_onset_s, events[2].t_hand_onset_s);
}

TEST(GaltEvents, NoEventsGiveOneResult) {
  const Trajectory still = EpisodeBuilder(50).trajectory();
  const std::vector<GaltResult> none = ComputeGaltEvents(still.view(), 20.0);
  ASSERT_EQ(none.size(), 1u);
  EXPECT_EQ(none[0].reason, GaltReason::kNoGrasp);
  const Trajectory five = EpisodeBuilder(5).trajectory();
  const std::vector<GaltResult> too_short = ComputeGaltEvents(five.view(), 20.0);
  ASSERT_EQ(too_short.size(), 1u);
  EXPECT_EQ(too_short[0].reason, GaltReason::kTooShort);
}

TEST(Galt, ReasonStringsAreTheReferences) {
  EXPECT_STREQ(ToString(GaltReason::kOk), "ok");
  EXPECT_STREQ(ToString(GaltReason::kOkPostAnchor), "ok_post_anchor");
  EXPECT_STREQ(ToString(GaltReason::kNoGrasp), "no_grasp");
  EXPECT_STREQ(ToString(GaltReason::kNoHandOnset), "no_hand_onset");
  EXPECT_STREQ(ToString(GaltReason::kNoFixation), "no_fixation");
  EXPECT_STREQ(ToString(GaltReason::kOutlierLow), "outlier_low");
  EXPECT_STREQ(ToString(GaltReason::kOutlierHigh), "outlier_high");
  EXPECT_STREQ(ToString(GaltReason::kAmbiguousArms), "ambiguous_arms");
  EXPECT_STREQ(ToString(GaltReason::kTooShort), "too_short");
}

TEST(Galt, RejectsBadInput) {
  const Trajectory episode = EpisodeBuilder(20).trajectory();
  EXPECT_THROW(ComputeGalt(episode.view(), 0.0), std::invalid_argument);
  EXPECT_THROW(ComputeGalt(episode.view(), std::nan("")), std::invalid_argument);
  ActionLayout layout;
  layout.right_gripper = action::kSize;
  EXPECT_THROW(ComputeGalt(episode.view(), 20.0, {}, layout), std::invalid_argument);
  const TrajectoryView missing_data{nullptr, 5, action::kSize};
  EXPECT_THROW(ComputeGaltBatch({episode.view(), missing_data}, 20.0), std::invalid_argument);
}

}  // namespace
}  // namespace tavis::kinematics
