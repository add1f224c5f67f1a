// How the appearance perturbation axis (engine::RenderPerturbation's textures, docs/
// perturbations.md) reaches what SceneRender draws: which scene instances are the table, the floor
// and the distractors, and each env's per-instance render::ProceduralTexture for
// RenderInputs::instance_texture. Without an appearance level nothing is textured and the
// renderer takes its untextured path, so the base scene renders exactly as before.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/render_perturbation.h"
#include "engine/world_model.h"
#include "render/procedural_texture.h"

namespace tavis::batch::perturb {

// Which of the axis's surfaces a scene instance is.
enum class TexturedSurface : uint8_t { kNone, kFloor, kTable, kDistractor };

// The table is the static part named "table" (engine::MakeTable); other static parts (shelves,
// screens) keep their colours. Distractors are the objects a perturbation flagged as such.
TexturedSurface SurfaceOfStaticPart(const engine::StaticPart& part);
TexturedSurface SurfaceOfObject(const engine::ObjectSpec& object);

// The textures episode `episode` shows on the floor, table and distractors, in that order: the
// level's, with the colours of a `colours: random` surface drawn from the axis's own random
// stream keyed by (perturbation.noise_seed, episode), so they repeat for any thread or slot.
struct EpisodeTextures {
  engine::SurfaceTexture floor;
  engine::SurfaceTexture table;
  engine::SurfaceTexture distractors;
};
EpisodeTextures TexturesOfEpisode(const engine::RenderPerturbation& perturbation, int64_t episode);

class AppearanceTextures {
 public:
  AppearanceTextures() = default;
  // surfaces: per scene instance (layout order). Inactive when the perturbation textures nothing.
  AppearanceTextures(const engine::RenderPerturbation& perturbation, std::vector<TexturedSurface> surfaces,
                     int num_envs);

  bool active() const { return !textures_.empty(); }
  // Env `env` shows episode `episode`: with random colours, its textures are redrawn when the
  // episode changed. Touches only env's rows, so distinct envs may be updated concurrently.
  void ShowEpisode(int env, int64_t episode);
  // [env][instance]; empty when inactive (RenderInputs::instance_texture: no textures).
  const std::vector<render::ProceduralTexture>& textures() const { return textures_; }

 private:
  void Fill(int env, const EpisodeTextures& episode_textures);

  engine::RenderPerturbation perturbation_;
  std::vector<TexturedSurface> surfaces_;  // [instance]
  bool random_ = false;                    // some surface draws its colours per episode
  std::vector<int64_t> shown_episode_;     // [env] the episode its textures were drawn for
  std::vector<render::ProceduralTexture> textures_;
};

}  // namespace tavis::batch::perturb
