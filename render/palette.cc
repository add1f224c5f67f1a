#include "render/palette.h"

#include <array>
#include <stdexcept>

namespace tavis::render {
namespace {

struct NamedAppearance {
  const char* name;
  Appearance appearance;
};

Appearance Plain(float r, float g, float b) {
  Appearance a;
  a.rgb = {r, g, b};
  return a;
}

Appearance Labelled(float r, float g, float b, LabelPattern label, float lr, float lg, float lb) {
  Appearance a = Plain(r, g, b);
  a.label = label;
  a.label_rgb = {lr, lg, lb};
  return a;
}

Appearance Emissive(float r, float g, float b) {
  Appearance a = Plain(r, g, b);
  a.emissive = true;
  return a;
}

const std::array<NamedAppearance, 16>& Palette() {
  static const std::array<NamedAppearance, 16> palette = {{
      {"floor", Plain(0.12f, 0.12f, 0.13f)},
      // Brushed-metal grey, brighter than the floor so the table edge reads clearly.
      {"table", Plain(0.38f, 0.38f, 0.40f)},
      {"robot_link", Plain(0.55f, 0.56f, 0.60f)},
      {"gripper", Plain(0.04f, 0.04f, 0.045f)},
      // Tomato soup can: red body, white band.
      {"soup_can", Labelled(0.60f, 0.03f, 0.02f, LabelPattern::kBand, 0.85f, 0.85f, 0.80f)},
      // Potted meat can: blue body, yellow band.
      {"meat_can", Labelled(0.03f, 0.08f, 0.50f, LabelPattern::kBand, 0.85f, 0.65f, 0.02f)},
      // Tuna can: gold side, silver lids.
      {"tuna_fish_can", Labelled(0.60f, 0.40f, 0.08f, LabelPattern::kCaps, 0.62f, 0.62f, 0.66f)},
      // Gelatin box: pink-red box with a white front panel.
      {"gelatin_box", Labelled(0.80f, 0.10f, 0.30f, LabelPattern::kFrontPanel, 0.85f, 0.85f, 0.85f)},
      // Pudding box: brown box with white stripes.
      {"pudding_box", Labelled(0.22f, 0.09f, 0.03f, LabelPattern::kStripes, 0.85f, 0.85f, 0.80f)},
      {"red_cube", Plain(0.9f, 0.1f, 0.1f)},
      {"cue_card", Emissive(0.9f, 0.9f, 0.9f)},
      {"signal_light", Emissive(0.9f, 0.05f, 0.05f)},
      // Reference 4.5-4.7 materials: wooden box walls and shelves, the monitor's frame and panel.
      {"wood", Plain(0.55f, 0.35f, 0.20f)},
      {"screen_frame", Plain(0.18f, 0.18f, 0.18f)},
      {"screen_panel", Plain(0.05f, 0.05f, 0.05f)},
      // The distractors perturbation axis's objects: each is given its own colour per episode
      // (BatchState::object_rgb, from configs/perturbations/distractors.yaml); this grey is never seen.
      {"distractor", Plain(0.5f, 0.5f, 0.5f)},
  }};
  return palette;
}

}  // namespace

const Appearance& PaletteAppearance(const std::string& name) {
  for (const NamedAppearance& entry : Palette()) {
    if (name == entry.name) return entry.appearance;
  }
  std::string known;
  for (const std::string& known_name : PaletteNames()) known += (known.empty() ? "" : ", ") + known_name;
  throw std::invalid_argument("unknown palette appearance '" + name + "' (known: " + known + ")");
}

std::vector<std::string> PaletteNames() {
  std::vector<std::string> names;
  for (const NamedAppearance& entry : Palette()) names.emplace_back(entry.name);
  return names;
}

}  // namespace tavis::render
