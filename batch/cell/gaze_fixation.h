// Where the head looks: per policy tick, the head camera's optical axis and a ring of rays a few
// pixels around it traced against the episode's objects and static parts, named by their role
// (target, cue, distractor, table, shelf, scene, nothing), kept as fixation segments; and the
// GALT verified by them (docs/gaze.md).
//
// The rays are traced analytically against each part's shape (exact for boxes and spheres, the
// bounding box of a cylinder or capsule), not through the renderer's Embree scene: a plain cell
// has no renderer, and the trace must be the same whether or not cameras are rendered. The
// robot's own links are transparent to the gaze ray (the grasping hand would otherwise stand in
// front of every fixation at the grasp), and the camera perturbation's offsets are not applied
// (the ray is the head's, as the neck commands it).
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/batch_state.h"
#include "engine/world_model.h"
#include "kinematics/action.h"
#include "kinematics/galt.h"
#include "kinematics/pose.h"

namespace tavis::batch::cell {

// What a gaze ray can land on; ToString gives the record's names.
enum class GazeTarget : uint8_t { kNothing, kTarget, kCue, kDistractor, kTable, kShelf, kScene };
const char* ToString(GazeTarget target);
bool ParseGazeTarget(const std::string& text, GazeTarget* target);

// One fixation: the policy steps [start, end) the gaze stayed on `target`.
struct FixationSegment {
  GazeTarget target = GazeTarget::kNothing;
  int start = 0;
  int end = 0;
  bool operator==(const FixationSegment& other) const {
    return target == other.target && start == other.start && end == other.end;
  }
};

// Radius of the cone around the image centre, in pixels of the 640 px wide head camera, and the
// rays of its ring (besides the centre ray).
inline constexpr double kGazeConeRadiusPx = 3.0;
inline constexpr int kGazeRingRays = 8;
// An object the neck cannot bring onto the optical axis (its pitch at a joint limit: Reachy2's
// head looks at most 30 degrees down, below which lie the table's objects) is fixated when the
// axis is within this of the closest the neck allows to it, as the cue_fixated stage counts it.
inline constexpr double kGazeAtLimitToleranceRad = 0.05;

class GazeTracer {
 public:
  // The robot's "head" camera; has_head() is false for a robot without one (nothing is traced).
  GazeTracer(const engine::WorldModel& model, const std::vector<std::string>& cue_objects);

  bool has_head() const { return head_camera_ >= 0; }
  // What env `env`'s head fixates in `state`, `action` being the policy's command in it: with a
  // neck joint held at a limit the command goes past (the head pressed as far as it turns), the
  // object on the commanded pose's centre ray (else most of its ring) if the camera sees it;
  // else the centre ray's object (target, cue or distractor) if it hits one, else the object most
  // rays of the ring hit (the first in ring order on a tie), else, with the neck's pitch at a
  // limit, the object it holds as close to the axis as it can (kGazeAtLimitToleranceRad), else
  // what the centre ray lands on (table, shelf, scene part or nothing).
  GazeTarget Trace(const engine::BatchState& state, int env, const kinematics::Action& action);

 private:
  struct Part {
    GazeTarget role = GazeTarget::kNothing;
    int object = -1;  // index in the model's objects; -1: a static part at X_WS
    Shape shape;
    RigidTransform X_WS = RigidTransform::Identity();
  };
  // The nearest part a ray meets: its role resolved for the env (kNothing: none), its object
  // index (-1: a static part or none) and the distance along the ray.
  struct Hit {
    GazeTarget role = GazeTarget::kNothing;
    int object = -1;
    double distance = std::numeric_limits<double>::infinity();
  };
  // The head camera's world pose with the joints at q.
  RigidTransform HeadCameraPose(const double* q);
  // The object the camera at X_WC has on its centre ray, else the one most of its ring's rays
  // meet; kNothing if none. With seen_from, a ray's object counts only where the straight line
  // from that point to where the ray meets it meets it first (the commanded pose's camera is not
  // where the real one is).
  GazeTarget ObjectOnAxis(const engine::BatchState& state, int env, const RigidTransform& X_WC,
                          const Vec3* seen_from) const;
  // With the neck's pitch at a joint limit, the object (of those it cannot centre, and that the
  // camera at p_W sees unblocked) whose direction is nearest the closest the neck allows, within
  // kGazeAtLimitToleranceRad; else kNothing.
  GazeTarget AtTheNecksLimit(const engine::BatchState& state, int env, const Vec3& p_W) const;
  // The nearest part the ray from p_W along the unit d_W meets, in env `env`.
  Hit Nearest(const engine::BatchState& state, int env, const Vec3& p_W, const Vec3& d_W) const;

  const engine::WorldModel& model_;
  int head_camera_ = -1;
  std::vector<Part> parts_;
  std::vector<RigidTransform> X_BL_;  // scratch: the head's chain of link poses
  std::vector<double> q_commanded_;   // scratch: the joints with the pressed neck joints commanded
  std::vector<Vec3> ring_C_;          // the ring's directions in the camera frame
};

// Appends one policy step's fixation to the segments (extending the last one if it continues).
void AppendFixation(GazeTarget target, int step, std::vector<FixationSegment>& segments);

// One of the task's gaze anchors in an episode (scenarios/gaze_anchor.h, measured by
// gaze_anchors.h): its lead time in seconds, unset where the episode has no such fixation or event.
struct AnchorLead {
  std::string name;
  std::optional<double> lead_s;
  bool operator==(const AnchorLead& other) const { return name == other.name && lead_s == other.lead_s; }
};

// An episode's gaze: its fixation segments and the GALT they verify.
struct GazeRecord {
  bool traced = false;  // false: no head to trace (the record then has no gaze keys)
  std::vector<FixationSegment> fixations;
  // For a successful episode with a GALT value: that value if the last fixation before the
  // grasp (the policy step before the gripper event) is on the target, else unset; the reason
  // "verified", "off_target" (fixated: what it was on), "no_galt" (no GALT value to verify).
  std::optional<double> galt_verified_s;
  std::string galt_verified_reason;
  std::optional<GazeTarget> pre_grasp_fixation;
  // Share of the policy steps in the window before the gripper event (the last lookback_s, as
  // GALT's) the gaze was on the target; unset without a gripper event.
  std::optional<double> gaze_on_target_ratio;
  // Whether a cue (the task's cue objects) was fixated before the reach onset; unset for a task
  // without a cue or an episode without a reach onset.
  std::optional<bool> cue_before_reach;
  // The task's anchors, in declared order (by name once read back from a record).
  std::vector<AnchorLead> anchors;
};

// The fixation at policy step `step`; kNothing outside the segments.
GazeTarget FixationAt(const std::vector<FixationSegment>& segments, int step);

// Fills the record's verified GALT, gaze-on-target ratio and look-before-reach from its
// fixations (at policy_hz) and the episode's GALT; `has_cue`: whether the task has cue objects.
void VerifyGalt(const std::optional<kinematics::GaltResult>& galt, double policy_hz, bool has_cue, GazeRecord& record);

// episodes.jsonl keys (when traced): "fixations": [[target, start, end], ...] in policy steps,
// "galt_verified_s", "galt_verified_reason", "pre_grasp_fixation", "gaze_on_target_ratio",
// "cue_before_reach" (null when unset), "gaze_anchors": {name: lead seconds or null}.
void AddGazeJson(const GazeRecord& record, nlohmann::json& line);
// Reads them back; a line without them leaves the record untraced. Throws std::invalid_argument
// naming a malformed key.
void ParseGazeJson(const nlohmann::json& line, GazeRecord& record);

// summary.json's "gaze": over the successful episodes with a GALT value, how many were verified
// and the fraction; the verified values' median; the gaze-on-target ratio's mean; look-before-
// reach's share. Null when no episode was traced (summary.json then has no "gaze").
nlohmann::json GazeSummaryJson(const std::vector<const GazeRecord*>& successful_episodes);

}  // namespace tavis::batch::cell
