#include "batch/perturb/perturbation_catalog.h"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <map>
#include <stdexcept>

#include "batch/perturb/distractor_placement.h"
#include "batch/perturb/episode_perturbation_levels.h"
#include "batch/perturb/perturbed_view.h"
#include "batch/perturb/surface_texture_yaml.h"
#include "configs/yaml_reader.h"
#include "render/camera.h"
#include "render/scene_layout.h"

namespace tavis::batch::perturb {
namespace {

using configs::Range;
using configs::YamlValue;

// One key a level of an axis may set: how it is read into the effect; returns the value as the
// level's settings record it.
struct LevelKey {
  const char* name;
  std::function<nlohmann::ordered_json(const YamlValue& value, engine::RenderPerturbation* effect)> read;
};

// Readers for scalar, 3-vector and textured-surface keys.
LevelKey Scalar(const char* name, Range range, double engine::RenderPerturbation::*field) {
  return {name, [range, field](const YamlValue& value, engine::RenderPerturbation* effect) {
            effect->*field = value.AsDouble(range);
            return nlohmann::ordered_json(effect->*field);
          }};
}
LevelKey Vector(const char* name, Range range, Vec3 engine::RenderPerturbation::*field) {
  return {name, [range, field](const YamlValue& value, engine::RenderPerturbation* effect) {
            effect->*field = value.AsVec3(range);
            return nlohmann::ordered_json(value.AsDoubles());
          }};
}
LevelKey Texture(const char* name, engine::SurfaceTexture engine::RenderPerturbation::*field) {
  return {name, [field](const YamlValue& value, engine::RenderPerturbation* effect) {
            SurfaceTextureEntry entry = ReadSurfaceTexture(value);
            effect->*field = entry.texture;
            return std::move(entry.settings);
          }};
}

const std::map<std::string, std::vector<LevelKey>>& AxisKeys() {
  using P = engine::RenderPerturbation;
  static const std::map<std::string, std::vector<LevelKey>> keys = {
      {"camera",
       {Vector("head_offset_m", {-0.3, 0.3, false, "m"}, &P::head_offset_m),
        Vector("head_rotation_deg", {-45.0, 45.0, false, "degrees"}, &P::head_rotation_deg),
        Vector("fixed_offset_m", {-0.5, 0.5, false, "m"}, &P::fixed_offset_m),
        Vector("fixed_rotation_deg", {-45.0, 45.0, false, "degrees"}, &P::fixed_rotation_deg),
        Scalar("head_fov_scale", {0.25, 2.0, false, ""}, &P::head_fov_scale),
        Scalar("fixed_fov_scale", {0.25, 2.0, false, ""}, &P::fixed_fov_scale)}},
      {"lighting",
       {Scalar("intensity_scale", {0.0, 10.0, true, ""}, &P::light_intensity_scale),
        Scalar("azimuth_deg", {-180.0, 180.0, false, "degrees"}, &P::light_azimuth_deg),
        Scalar("elevation_deg", {-85.0, 85.0, false, "degrees"}, &P::light_elevation_deg),
        Scalar("colour_temperature_k", {1000.0, 40000.0, false, "K"}, &P::colour_temperature_k)}},
      {"sensor",
       {Scalar("blur_sigma_px", {0.0, 20.0, false, "pixels"}, &P::blur_sigma_px),
        Scalar("noise_stddev", {0.0, 128.0, false, "8-bit levels"}, &P::noise_stddev)}},
      {"appearance",
       {Texture("table", &P::table_texture), Texture("floor", &P::floor_texture),
        Texture("distractors", &P::distractor_texture)}},
  };
  return keys;
}

std::string Join(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

std::string AxisPath(const std::string& config_dir, const std::string& axis) {
  return (std::filesystem::path(config_dir) / "perturbations" / (axis + ".yaml")).string();
}

// Values that pass their key's range but not the renderer (an angle of view of 180 degrees, a
// light below the horizon) are refused while the file is read, naming the key.
void CheckRenderable(const YamlValue& level, const engine::RenderPerturbation& effect) {
  auto check = [&](const char* key, const std::function<void()>& apply) {
    if (!level.Optional(key)) return;
    try {
      apply();
    } catch (const std::invalid_argument& error) {
      level.Required(key).Fail(error.what());
    }
  };
  check("head_fov_scale", [&] { PerturbedCameraSpec(render::HeadCameraSpec(), effect); });
  check("fixed_fov_scale", [&] { PerturbedCameraSpec(render::FixedCameraSpec(), effect); });
  check("elevation_deg", [&] {
    render::LightingSpec lighting;
    PerturbLighting(effect, &lighting);
  });
}

}  // namespace

const std::vector<std::string>& PerturbationAxisNames() {
  static const std::vector<std::string> names = {"camera",      "sensor",   "lighting", "appearance",
                                                 "distractors", "language", "runtime"};
  return names;
}

PerturbationChoice ParsePerturbationChoice(const std::string& text) {
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size() ||
      text.find(':', colon + 1) != std::string::npos) {
    throw std::invalid_argument("perturbation '" + text +
                                "' is not AXIS:LEVEL (axes: " + Join(PerturbationAxisNames()) + ")");
  }
  PerturbationChoice choice{text.substr(0, colon), text.substr(colon + 1)};
  const std::vector<std::string>& axes = PerturbationAxisNames();
  if (std::find(axes.begin(), axes.end(), choice.axis) == axes.end()) {
    throw std::invalid_argument("perturbation '" + text + "': unknown axis '" + choice.axis + "' (axes: " + Join(axes) +
                                ")");
  }
  return choice;
}

std::string PerturbationLabelSuffix(const std::vector<std::string>& choices) {
  std::string suffix;
  for (const std::string& text : choices) {
    const PerturbationChoice choice = ParsePerturbationChoice(text);
    suffix += "." + choice.axis + "." + choice.level;
  }
  return suffix;
}

std::vector<PerturbationLevel> LoadPerturbationAxis(const std::string& config_dir, const std::string& axis) {
  const auto keys = AxisKeys().find(axis);
  const EpisodeLevelReader episode_reader = FindEpisodeLevelReader(axis);
  if (keys == AxisKeys().end() && episode_reader == nullptr) {
    throw std::invalid_argument("unknown perturbation axis '" + axis + "' (axes: " + Join(PerturbationAxisNames()) +
                                ")");
  }
  const YamlValue root = YamlValue::LoadFile(AxisPath(config_dir, axis));
  const YamlValue axis_value = root.Required("axis");
  if (axis_value.AsString() != axis)
    axis_value.Fail("the file of axis '" + axis + "' must say axis: " + axis + ", got " + axis_value.Text());
  root.Optional("description");
  std::vector<PerturbationLevel> levels;
  const YamlValue level_list = root.Required("levels");
  if (!level_list.IsSequence() || level_list.Elements().empty())
    level_list.Fail("must be a non-empty list of levels, got " + level_list.Text());
  for (const YamlValue& entry : level_list.Elements()) {
    PerturbationLevel level;
    level.axis = axis;
    const YamlValue name = entry.Required("name");
    level.name = name.AsString();
    // Level names become parts of sweep labels and folder names.
    const bool plain = std::all_of(level.name.begin(), level.name.end(), [](unsigned char c) {
      return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-';
    });
    if (level.name.empty() || level.name.size() > 32 || !plain || level.name == "none") {
      name.Fail("a level name must be 1 to 32 lower-case letters, digits or '-', and not 'none', got " + name.Text());
    }
    for (const PerturbationLevel& other : levels) {
      if (other.name == level.name) name.Fail("level '" + level.name + "' is declared twice");
    }
    level.description = entry.String("description");
    level.settings["name"] = level.name;
    if (episode_reader != nullptr) {
      // Its keys are required where a level needs them, so it cannot be the base scene.
      episode_reader(root, entry, &level.episode_effect, &level.settings);
      entry.ExpectNoOtherKeys();
      levels.push_back(std::move(level));
      continue;
    }
    for (const LevelKey& key : keys->second) {
      const auto value = entry.Optional(key.name);
      if (!value) continue;
      level.settings[key.name] = key.read(*value, &level.effect);
    }
    entry.ExpectNoOtherKeys();
    if (level.settings.size() == 1) {
      std::string names;
      for (const LevelKey& key : keys->second) names += std::string(names.empty() ? "" : ", ") + key.name;
      entry.Fail("level '" + level.name + "' sets none of its axis's keys (" + names +
                 "), so it would be the base scene");
    }
    CheckRenderable(entry, level.effect);
    levels.push_back(std::move(level));
  }
  root.ExpectNoOtherKeys();
  return levels;
}

std::vector<PerturbationLevel> ResolvePerturbations(const std::string& config_dir,
                                                    const std::vector<std::string>& choices) {
  std::vector<PerturbationLevel> chosen;
  for (const std::string& text : choices) {
    const PerturbationChoice choice = ParsePerturbationChoice(text);
    for (const PerturbationLevel& earlier : chosen) {
      if (earlier.axis == choice.axis) {
        throw std::invalid_argument("perturbation '" + text + "': axis '" + choice.axis + "' is already chosen (" +
                                    earlier.axis + ":" + earlier.name + "); give one level per axis");
      }
    }
    std::vector<PerturbationLevel> levels = LoadPerturbationAxis(config_dir, choice.axis);
    std::vector<std::string> names;
    bool found = false;
    for (PerturbationLevel& level : levels) {
      names.push_back(level.name);
      if (level.name == choice.level) {
        chosen.push_back(std::move(level));
        found = true;
        break;
      }
    }
    if (!found) {
      throw std::invalid_argument("perturbation '" + text + "': axis '" + choice.axis + "' has no level '" +
                                  choice.level + "' (levels in " + AxisPath(config_dir, choice.axis) + ": " +
                                  Join(names) + ")");
    }
  }
  return chosen;
}

engine::RenderPerturbation CombinePerturbations(const std::vector<PerturbationLevel>& levels, uint64_t seed) {
  engine::RenderPerturbation combined;
  for (const PerturbationLevel& level : levels) {
    const engine::RenderPerturbation& e = level.effect;
    if (level.axis == "camera") {
      combined.head_offset_m = e.head_offset_m;
      combined.head_rotation_deg = e.head_rotation_deg;
      combined.fixed_offset_m = e.fixed_offset_m;
      combined.fixed_rotation_deg = e.fixed_rotation_deg;
      combined.head_fov_scale = e.head_fov_scale;
      combined.fixed_fov_scale = e.fixed_fov_scale;
    } else if (level.axis == "lighting") {
      combined.light_intensity_scale = e.light_intensity_scale;
      combined.light_azimuth_deg = e.light_azimuth_deg;
      combined.light_elevation_deg = e.light_elevation_deg;
      combined.colour_temperature_k = e.colour_temperature_k;
    } else if (level.axis == "sensor") {
      combined.blur_sigma_px = e.blur_sigma_px;
      combined.noise_stddev = e.noise_stddev;
    } else if (level.axis == "appearance") {
      combined.table_texture = e.table_texture;
      combined.floor_texture = e.floor_texture;
      combined.distractor_texture = e.distractor_texture;
    }
  }
  combined.noise_seed = seed;
  return combined;
}

engine::EpisodePerturbation CombineEpisodePerturbations(const std::vector<PerturbationLevel>& levels, uint64_t seed) {
  engine::EpisodePerturbation combined;
  for (const PerturbationLevel& level : levels) {
    // A level sets its own axis's part only (episode_perturbation_levels.h), and a view level none.
    const engine::EpisodePerturbation& e = level.episode_effect;
    if (e.adds_distractors()) combined.distractors = e.distractors;
    if (e.paraphrases_prompt()) combined.language = e.language;
    if (e.moves_target()) combined.target_move = e.target_move;
  }
  combined.seed = seed;
  return combined;
}

nlohmann::json PerturbationsJson(const std::vector<PerturbationLevel>& levels) {
  nlohmann::json list = nlohmann::json::array();
  for (const PerturbationLevel& level : levels) {
    list.push_back(
        {{"axis", level.axis}, {"level", level.name}, {"settings", nlohmann::json::parse(level.settings.dump())}});
  }
  return list;
}

void ApplyPerturbations(const std::string& config_dir, const std::vector<std::string>& choices, uint64_t seed,
                        engine::WorldModel* model) {
  if (choices.empty()) return;
  ApplyPerturbationLevels(ResolvePerturbations(config_dir, choices), seed, model);
}

void ApplyPerturbationLevels(const std::vector<PerturbationLevel>& levels, uint64_t seed, engine::WorldModel* model) {
  if (levels.empty()) return;
  model->view_perturbation = CombinePerturbations(levels, seed);
  model->episode_perturbation = CombineEpisodePerturbations(levels, seed);
  AddDistractorObjects(model);
}

}  // namespace tavis::batch::perturb
