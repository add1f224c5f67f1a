// The visibility audit: does each task's information sit in the camera the paper says? For every
// episode it measures how much of the task's deciding objects (the target, and the cue card or
// signal light of the tasks that have one) each camera sees at reset and at the scripted expert's
// fixation: the first control tick at which the expert's gaze is settled on that object (for
// peeking-box, once both wrists have reached their peek poses).
//
// Visible: at least kVisibleFraction of the object's own pixels show in the camera's object-id
// image, where its own pixels are those it covers in that camera rendered with nothing else in
// the scene (no table, walls, robot or other objects). A camera the task blacks out
// (blocked-clutter-pick-cube's head) sees nothing.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "batch/episode_driver.h"
#include "batch/scene/scene_spec.h"

namespace tavis::batch::audit {

inline constexpr double kVisibleFraction = 0.01;

struct AuditConfig {
  // The task, robot, split, seed, perturbation levels and config dir audited (planned by
  // scene::PlanScene, as every front end plans its scene).
  scene::SceneSpec scene;
  int episodes = 96;
  int envs = 32;  // parallel env slots (results do not depend on it)
  int image_width = 224;
  int image_height = 224;
};

// Visible fraction of one object in every camera (AuditResult::cameras order), 0..1.
using CameraFractions = std::vector<double>;

struct ObjectAudit {
  CameraFractions at_reset;
  std::optional<CameraFractions> at_fixation;  // empty: the expert never fixated it
  int fixation_tick = -1;                      // control tick of the fixation, -1 if none
};

struct EpisodeAudit {
  int64_t episode = 0;
  std::vector<ObjectAudit> objects;  // AuditResult::objects order
};

struct AuditResult {
  AuditConfig config;
  std::vector<std::string> objects;    // "target", then the cue's model name if the task has one
  std::vector<std::string> cameras;    // SceneCameraNames()
  std::vector<EpisodeAudit> episodes;  // ordered by episode index
  double wall_s = 0.0;

  // Episodes in which the object counts as visible in the camera.
  int VisibleAtReset(int object, int camera) const;
  int VisibleAtFixation(int object, int camera) const;
  // Episodes in which the expert fixated the object.
  int Fixated(int object) const;
};

// Runs the task's scripted expert over config.episodes episodes (episode i with the randomness of
// (seed, i), as in an evaluation cell), rendering all four cameras with object ids at reset and
// at each audited object's fixation only; an episode stops once every audited object has been
// sampled or it ends. Results do not depend on the thread count or config.envs. Throws
// std::invalid_argument / configs::ConfigError for bad settings.
AuditResult RunVisibilityAudit(const AuditConfig& config, const ProgressCallback& progress = nullptr);

}  // namespace tavis::batch::audit
