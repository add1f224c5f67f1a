#include "batch/perturb/perturbed_appearance.h"

#include <limits>
#include <utility>

#include "engine/random.h"

namespace tavis::batch::perturb {
namespace {

constexpr const char* kTablePartName = "table";
// Random colours stay clear of pure black and white, so that both colours of a pattern are lit
// and neither saturates.
constexpr double kRandomColourLow = 0.05;
constexpr double kRandomColourHigh = 0.95;
constexpr int64_t kNoEpisodeShown = std::numeric_limits<int64_t>::min();

Eigen::Vector3f RandomColour(engine::RandomStream* rng) {
  Eigen::Vector3f rgb;
  for (int channel = 0; channel < 3; ++channel)
    rgb[channel] = static_cast<float>(rng->Uniform(kRandomColourLow, kRandomColourHigh));
  return rgb;
}

// Both colours are drawn for every surface whether it asks or not, in a fixed order, so that one
// surface's draws never depend on another's settings.
void DrawColours(engine::RandomStream* rng, engine::SurfaceTexture* texture) {
  const Eigen::Vector3f a = RandomColour(rng);
  const Eigen::Vector3f b = RandomColour(rng);
  if (!texture->random_colours) return;
  texture->colour_a = a;
  texture->colour_b = b;
}

}  // namespace

TexturedSurface SurfaceOfStaticPart(const engine::StaticPart& part) {
  return part.name == kTablePartName ? TexturedSurface::kTable : TexturedSurface::kNone;
}

TexturedSurface SurfaceOfObject(const engine::ObjectSpec& object) {
  return object.distractor ? TexturedSurface::kDistractor : TexturedSurface::kNone;
}

EpisodeTextures TexturesOfEpisode(const engine::RenderPerturbation& perturbation, int64_t episode) {
  EpisodeTextures textures{perturbation.floor_texture, perturbation.table_texture, perturbation.distractor_texture};
  engine::RandomStream rng(perturbation.noise_seed, engine::RandomStreamId::kAppearance,
                           static_cast<uint64_t>(episode));
  DrawColours(&rng, &textures.floor);
  DrawColours(&rng, &textures.table);
  DrawColours(&rng, &textures.distractors);
  return textures;
}

AppearanceTextures::AppearanceTextures(const engine::RenderPerturbation& perturbation,
                                       std::vector<TexturedSurface> surfaces, int num_envs)
    : perturbation_(perturbation), surfaces_(std::move(surfaces)) {
  if (!perturbation_.changes_surfaces()) return;
  random_ = perturbation_.floor_texture.random_colours || perturbation_.table_texture.random_colours ||
            perturbation_.distractor_texture.random_colours;
  shown_episode_.assign(static_cast<std::size_t>(num_envs), kNoEpisodeShown);
  textures_.resize(static_cast<std::size_t>(num_envs) * surfaces_.size());
  // Without random colours every episode shows the level's textures: filled once here.
  const EpisodeTextures fixed{perturbation_.floor_texture, perturbation_.table_texture,
                              perturbation_.distractor_texture};
  for (int env = 0; env < num_envs; ++env) Fill(env, fixed);
}

void AppearanceTextures::ShowEpisode(int env, int64_t episode) {
  if (!random_ || shown_episode_[static_cast<std::size_t>(env)] == episode) return;
  shown_episode_[static_cast<std::size_t>(env)] = episode;
  Fill(env, TexturesOfEpisode(perturbation_, episode));
}

void AppearanceTextures::Fill(int env, const EpisodeTextures& episode_textures) {
  const render::ProceduralTexture floor = render::MakeProceduralTexture(episode_textures.floor);
  const render::ProceduralTexture table = render::MakeProceduralTexture(episode_textures.table);
  const render::ProceduralTexture distractors = render::MakeProceduralTexture(episode_textures.distractors);
  render::ProceduralTexture* row = textures_.data() + static_cast<std::size_t>(env) * surfaces_.size();
  for (std::size_t i = 0; i < surfaces_.size(); ++i) {
    switch (surfaces_[i]) {
      case TexturedSurface::kNone: row[i] = render::ProceduralTexture(); break;
      case TexturedSurface::kFloor: row[i] = floor; break;
      case TexturedSurface::kTable: row[i] = table; break;
      case TexturedSurface::kDistractor: row[i] = distractors; break;
    }
  }
}

}  // namespace tavis::batch::perturb
