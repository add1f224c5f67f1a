#include "batch/cell/gaze_fixation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "kinematics/forward_kinematics.h"
#include "render/camera.h"
#include "scenarios/expert/gaze.h"

namespace tavis::batch::cell {

namespace {

constexpr std::array<const char*, 7> kTargetNames = {"nothing", "target", "cue",  "distractor",
                                                     "table",   "shelf",  "scene"};
constexpr double kNoHit = std::numeric_limits<double>::infinity();

bool Contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// Distance along the unit ray (p, d), both in the shape's frame, to its first hit; kNoHit if none.
double HitDistance(const Shape& shape, const Vec3& p, const Vec3& d) {
  if (shape.kind == ShapeKind::kSphere) {
    const double b = p.dot(d), c = p.squaredNorm() - shape.Radius() * shape.Radius();
    const double disc = b * b - c;
    if (disc < 0.0) return kNoHit;
    const double root = std::sqrt(disc);
    const double t = -b - root >= 0.0 ? -b - root : -b + root;
    return t >= 0.0 ? t : kNoHit;
  }
  // The slab test on the bounding box (exact for a box).
  const Vec3 half = BoundingHalfSize(shape);
  double t_near = 0.0, t_far = kNoHit;
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(d[axis]) < 1e-12) {
      if (std::abs(p[axis]) > half[axis]) return kNoHit;
      continue;
    }
    double t0 = (-half[axis] - p[axis]) / d[axis], t1 = (half[axis] - p[axis]) / d[axis];
    if (t0 > t1) std::swap(t0, t1);
    t_near = std::max(t_near, t0);
    t_far = std::min(t_far, t1);
    if (t_near > t_far) return kNoHit;
  }
  return t_near;
}

// A neck pitch within this of a joint limit is at the limit (the PD-held joint sits a hair off it).
constexpr double kAtLimitRad = 0.01;

bool IsObject(GazeTarget target) {
  return target == GazeTarget::kTarget || target == GazeTarget::kCue || target == GazeTarget::kDistractor;
}

}  // namespace

const char* ToString(GazeTarget target) { return kTargetNames[static_cast<std::size_t>(target)]; }

bool ParseGazeTarget(const std::string& text, GazeTarget* target) {
  for (std::size_t i = 0; i < kTargetNames.size(); ++i) {
    if (text == kTargetNames[i]) {
      *target = static_cast<GazeTarget>(i);
      return true;
    }
  }
  return false;
}

GazeTracer::GazeTracer(const engine::WorldModel& model, const std::vector<std::string>& cue_objects)
    : model_(model), X_BL_(static_cast<std::size_t>(model.robot.num_links()), RigidTransform::Identity()) {
  for (std::size_t c = 0; c < model.robot.cameras.size(); ++c) {
    if (model.robot.cameras[c].name == "head") head_camera_ = static_cast<int>(c);
  }
  for (int i = 0; i < model.num_objects(); ++i) {
    const engine::ObjectSpec& object = model.objects[static_cast<std::size_t>(i)];
    // The role of an object is resolved per env at the trace (the target differs per episode).
    parts_.push_back({Contains(cue_objects, object.name) ? GazeTarget::kCue : GazeTarget::kDistractor, i, object.shape,
                      RigidTransform::Identity()});
  }
  for (const engine::StaticPart& part : model.static_parts) {
    if (part.shape.kind == ShapeKind::kPlane) continue;
    GazeTarget role = GazeTarget::kScene;
    if (Contains(cue_objects, part.name)) {
      role = GazeTarget::kCue;
    } else if (part.name.find("shelf") != std::string::npos) {
      role = GazeTarget::kShelf;
    } else if (part.name.find("table") != std::string::npos) {
      role = GazeTarget::kTable;
    }
    parts_.push_back({role, -1, part.shape, part.X_WS});
  }
  if (head_camera_ >= 0) {
    const double fx = model.robot.cameras[static_cast<std::size_t>(head_camera_)].focal_length_mm /
                      render::kHorizontalApertureMm * 640.0;
    const double r = kGazeConeRadiusPx / fx;
    for (int k = 0; k < kGazeRingRays; ++k) {
      const double a = 2.0 * M_PI * k / kGazeRingRays;
      ring_C_.push_back(Vec3(1.0, r * std::cos(a), r * std::sin(a)).normalized());
    }
  }
}

GazeTracer::Hit GazeTracer::Nearest(const engine::BatchState& state, int env, const Vec3& p_W, const Vec3& d_W) const {
  Hit hit;
  for (const Part& part : parts_) {
    RigidTransform X_WS = part.X_WS;
    GazeTarget role = part.role;
    if (part.object >= 0) {
      if (state.object_enabled_at(env, part.object) == 0) continue;
      X_WS = MakeTransform(state.ObjectPosition(env, part.object),
                           state.ObjectOrientation(env, part.object).normalized().toRotationMatrix());
      if (part.object == state.target(env)) role = GazeTarget::kTarget;
    }
    const Mat3 R_SW = X_WS.linear().transpose();
    const double t = HitDistance(part.shape, R_SW * (p_W - X_WS.translation()), R_SW * d_W);
    if (t < hit.distance) hit = {role, part.object, t};
  }
  return hit;
}

RigidTransform GazeTracer::HeadCameraPose(const double* q) {
  const kinematics::RobotModel& robot = model_.robot;
  const kinematics::CameraMount& mount = robot.cameras[static_cast<std::size_t>(head_camera_)];
  kinematics::ComputeLinkPoseChain(robot, q, mount.link, X_BL_.data());
  return MakeTransform(robot.root_world, Mat3::Identity()) * kinematics::CameraPose(robot, head_camera_, X_BL_.data());
}

GazeTarget GazeTracer::ObjectOnAxis(const engine::BatchState& state, int env, const RigidTransform& X_WC,
                                    const Vec3* seen_from) const {
  const Vec3 p_W = X_WC.translation();
  // The object a ray along d_C (camera frame) meets first, if the camera at seen_from sees that
  // point of it first too.
  const auto object_hit = [&](const Vec3& d_C) {
    const Vec3 d_W = X_WC.linear() * d_C;
    const Hit hit = Nearest(state, env, p_W, d_W);
    if (!IsObject(hit.role)) return GazeTarget::kNothing;
    if (seen_from != nullptr) {
      const Vec3 point = p_W + hit.distance * d_W;
      if (Nearest(state, env, *seen_from, (point - *seen_from).normalized()).object != hit.object)
        return GazeTarget::kNothing;
    }
    return hit.role;
  };
  const GazeTarget centre = object_hit(Vec3::UnitX());
  if (centre != GazeTarget::kNothing) return centre;
  std::array<int, kTargetNames.size()> counts{};
  GazeTarget best = GazeTarget::kNothing;
  for (const Vec3& d_C : ring_C_) {
    const GazeTarget ring = object_hit(d_C);
    if (ring == GazeTarget::kNothing) continue;
    const int count = ++counts[static_cast<std::size_t>(ring)];
    if (best == GazeTarget::kNothing || count > counts[static_cast<std::size_t>(best)]) best = ring;
  }
  return best;
}

GazeTarget GazeTracer::Trace(const engine::BatchState& state, int env, const kinematics::Action& action) {
  const kinematics::RobotModel& robot = model_.robot;
  const double* q = state.q_row(env);
  // A neck joint held at its limit while the policy commands it past the limit (Reachy2's head
  // turned down to a table-top object it cannot centre) says no more than "this far"; the command
  // says where the head is pointed. The commanded pose is the measured one with each such joint
  // at its command; what its rays meet counts where the real camera sees it.
  q_commanded_.assign(q, q + robot.num_joints());
  bool pressed = false;
  for (int k = 0; k < kinematics::kNeckDof; ++k) {
    const int j = robot.neck_joints[static_cast<std::size_t>(k)];
    const kinematics::Joint& joint = robot.joints[static_cast<std::size_t>(j)];
    const double command = action[kinematics::action::kNeck[k]];
    if ((q[j] >= joint.upper - kAtLimitRad && command > joint.upper + kAtLimitRad) ||
        (q[j] <= joint.lower + kAtLimitRad && command < joint.lower - kAtLimitRad)) {
      q_commanded_[static_cast<std::size_t>(j)] = command;
      pressed = true;
    }
  }
  const RigidTransform X_WC = HeadCameraPose(q);
  const Vec3 p_W = X_WC.translation();
  if (pressed) {
    const GazeTarget commanded = ObjectOnAxis(state, env, HeadCameraPose(q_commanded_.data()), &p_W);
    if (commanded != GazeTarget::kNothing) return commanded;
  }
  const GazeTarget on_axis = ObjectOnAxis(state, env, X_WC, nullptr);
  if (on_axis != GazeTarget::kNothing) return on_axis;
  const GazeTarget limited = AtTheNecksLimit(state, env, p_W);
  return limited != GazeTarget::kNothing ? limited : Nearest(state, env, p_W, X_WC.linear().col(0)).role;
}

GazeTarget GazeTracer::AtTheNecksLimit(const engine::BatchState& state, int env, const Vec3& p_W) const {
  const kinematics::RobotModel& robot = model_.robot;
  const double* q = state.q_row(env);
  const kinematics::Joint& pitch = robot.joints[static_cast<std::size_t>(robot.neck_joints[1])];
  const double q_pitch = q[robot.neck_joints[1]];
  if (q_pitch > pitch.lower + kAtLimitRad && q_pitch < pitch.upper - kAtLimitRad) return GazeTarget::kNothing;
  double closest = kGazeAtLimitToleranceRad;
  GazeTarget fixated = GazeTarget::kNothing;
  for (const Part& part : parts_) {
    if (part.object < 0 || state.object_enabled_at(env, part.object) == 0) continue;
    const Vec3 centre = state.ObjectPosition(env, part.object);
    const double allowed = scenarios::expert::ClosestGazeError(robot, q, centre);
    if (allowed <= kAtLimitRad) continue;  // the neck could centre it: it looks elsewhere
    const double beyond = scenarios::expert::GazeError(robot, q, centre) - allowed;
    if (beyond > closest) continue;
    // Seen, not only aimed at: nothing (a box's wall, a screen, another object) stands between the
    // camera and the object's centre, as the centre ray would have to pass.
    if (Nearest(state, env, p_W, (centre - p_W).normalized()).object == part.object) {
      closest = beyond;
      fixated = part.object == state.target(env) ? GazeTarget::kTarget : part.role;
    }
  }
  return fixated;
}

void AppendFixation(GazeTarget target, int step, std::vector<FixationSegment>& segments) {
  if (!segments.empty() && segments.back().target == target && segments.back().end == step) {
    segments.back().end = step + 1;
  } else {
    segments.push_back({target, step, step + 1});
  }
}

GazeTarget FixationAt(const std::vector<FixationSegment>& segments, int step) {
  for (const FixationSegment& segment : segments) {
    if (step >= segment.start && step < segment.end) return segment.target;
  }
  return GazeTarget::kNothing;
}

void VerifyGalt(const std::optional<kinematics::GaltResult>& galt, double policy_hz, bool has_cue, GazeRecord& record) {
  if (!record.traced) return;
  const kinematics::GaltParams params;
  // The policy step a time (s) falls in.
  const auto step_at = [&](double t) { return static_cast<int>(std::floor(t * policy_hz + 1e-9)); };
  if (galt && galt->t_hand_arrival_s) {
    const int grasp = step_at(*galt->t_hand_arrival_s);
    const int first = std::max(0, grasp - static_cast<int>(std::lround(params.lookback_s * policy_hz)));
    int on_target = 0;
    for (int step = first; step < grasp; ++step) on_target += FixationAt(record.fixations, step) == GazeTarget::kTarget;
    if (grasp > first) record.gaze_on_target_ratio = static_cast<double>(on_target) / (grasp - first);
    if (has_cue && galt->t_hand_onset_s) {
      const int onset = step_at(*galt->t_hand_onset_s);
      bool seen = false;
      for (const FixationSegment& segment : record.fixations)
        seen |= segment.target == GazeTarget::kCue && segment.start < onset;
      record.cue_before_reach = seen;
    }
  }
  if (!galt || !galt->galt_s || !galt->t_hand_arrival_s) {
    record.galt_verified_reason = "no_galt";
    return;
  }
  record.pre_grasp_fixation = FixationAt(record.fixations, std::max(0, step_at(*galt->t_hand_arrival_s) - 1));
  if (*record.pre_grasp_fixation == GazeTarget::kTarget) {
    record.galt_verified_s = galt->galt_s;
    record.galt_verified_reason = "verified";
  } else {
    record.galt_verified_reason = "off_target";
  }
}

void AddGazeJson(const GazeRecord& record, nlohmann::json& line) {
  if (!record.traced) return;
  nlohmann::json fixations = nlohmann::json::array();
  for (const FixationSegment& segment : record.fixations) {
    fixations.push_back({ToString(segment.target), segment.start, segment.end});
  }
  line["fixations"] = std::move(fixations);
  line["galt_verified_s"] = record.galt_verified_s ? nlohmann::json(*record.galt_verified_s) : nlohmann::json();
  line["galt_verified_reason"] =
      record.galt_verified_reason.empty() ? nlohmann::json() : nlohmann::json(record.galt_verified_reason);
  line["pre_grasp_fixation"] =
      record.pre_grasp_fixation ? nlohmann::json(ToString(*record.pre_grasp_fixation)) : nlohmann::json();
  line["gaze_on_target_ratio"] =
      record.gaze_on_target_ratio ? nlohmann::json(*record.gaze_on_target_ratio) : nlohmann::json();
  line["cue_before_reach"] = record.cue_before_reach ? nlohmann::json(*record.cue_before_reach) : nlohmann::json();
  nlohmann::json anchors = nlohmann::json::object();
  for (const AnchorLead& anchor : record.anchors)
    anchors[anchor.name] = anchor.lead_s ? nlohmann::json(*anchor.lead_s) : nlohmann::json();
  line["gaze_anchors"] = std::move(anchors);
}

void ParseGazeJson(const nlohmann::json& line, GazeRecord& record) {
  if (!line.contains("fixations")) return;
  const auto bad = [](const std::string& key) {
    return std::invalid_argument("episode record: malformed \"" + key + "\"");
  };
  const nlohmann::json& fixations = line.at("fixations");
  if (!fixations.is_array()) throw bad("fixations");
  record.traced = true;
  for (const nlohmann::json& entry : fixations) {
    FixationSegment segment;
    if (!entry.is_array() || entry.size() != 3 || !entry[0].is_string() || !entry[1].is_number_integer() ||
        !entry[2].is_number_integer() || !ParseGazeTarget(entry[0].get<std::string>(), &segment.target)) {
      throw bad("fixations");
    }
    segment.start = entry[1].get<int>();
    segment.end = entry[2].get<int>();
    record.fixations.push_back(segment);
  }
  const auto number = [&](const char* key, std::optional<double>& out) {
    if (!line.contains(key) || line.at(key).is_null()) return;
    if (!line.at(key).is_number()) throw bad(key);
    out = line.at(key).get<double>();
  };
  number("galt_verified_s", record.galt_verified_s);
  number("gaze_on_target_ratio", record.gaze_on_target_ratio);
  if (line.contains("galt_verified_reason") && line.at("galt_verified_reason").is_string()) {
    record.galt_verified_reason = line.at("galt_verified_reason").get<std::string>();
  }
  if (line.contains("pre_grasp_fixation") && !line.at("pre_grasp_fixation").is_null()) {
    GazeTarget target;
    if (!line.at("pre_grasp_fixation").is_string() ||
        !ParseGazeTarget(line.at("pre_grasp_fixation").get<std::string>(), &target)) {
      throw bad("pre_grasp_fixation");
    }
    record.pre_grasp_fixation = target;
  }
  if (line.contains("cue_before_reach") && !line.at("cue_before_reach").is_null()) {
    if (!line.at("cue_before_reach").is_boolean()) throw bad("cue_before_reach");
    record.cue_before_reach = line.at("cue_before_reach").get<bool>();
  }
  // A record written before anchors existed has none.
  if (line.contains("gaze_anchors")) {
    const nlohmann::json& anchors = line.at("gaze_anchors");
    if (!anchors.is_object()) throw bad("gaze_anchors");
    for (const auto& [name, lead] : anchors.items()) {
      if (!lead.is_null() && !lead.is_number()) throw bad("gaze_anchors");
      record.anchors.push_back({name, lead.is_null() ? std::nullopt : std::optional<double>(lead.get<double>())});
    }
  }
}

nlohmann::json GazeSummaryJson(const std::vector<const GazeRecord*>& successful_episodes) {
  int traced = 0, with_galt = 0, verified = 0, ratios = 0, cue_known = 0, cue_seen = 0;
  double ratio_sum = 0.0;
  std::vector<double> values;
  nlohmann::json reasons = nlohmann::json::object();
  for (const GazeRecord* record : successful_episodes) {
    if (!record->traced) continue;
    ++traced;
    if (!record->galt_verified_reason.empty()) {
      reasons[record->galt_verified_reason] = reasons.value(record->galt_verified_reason, 0) + 1;
    }
    if (record->galt_verified_reason != "no_galt") ++with_galt;
    if (record->galt_verified_s) {
      ++verified;
      values.push_back(*record->galt_verified_s);
    }
    if (record->gaze_on_target_ratio) {
      ++ratios;
      ratio_sum += *record->gaze_on_target_ratio;
    }
    if (record->cue_before_reach) {
      ++cue_known;
      cue_seen += *record->cue_before_reach;
    }
  }
  if (traced == 0) return nullptr;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  nlohmann::json median = nullptr;
  if (n > 0) median = n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
  const auto share = [](int part, int whole) {
    return whole > 0 ? nlohmann::json(double(part) / whole) : nlohmann::json();
  };
  return {{"n_episodes", traced},
          {"n_with_galt", with_galt},
          {"n_verified", verified},
          {"verified_fraction", share(verified, with_galt)},
          {"galt_verified_median_s", median},
          {"reasons", reasons},
          {"gaze_on_target_ratio_mean", ratios > 0 ? nlohmann::json(ratio_sum / ratios) : nlohmann::json()},
          {"cue_before_reach_fraction", share(cue_seen, cue_known)}};
}

}  // namespace tavis::batch::cell
