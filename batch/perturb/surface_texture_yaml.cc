#include "batch/perturb/surface_texture_yaml.h"

#include <string>
#include <utility>
#include <vector>

namespace tavis::batch::perturb {
namespace {

using configs::Range;
using configs::YamlValue;
using engine::TexturePattern;

// Wood's rings wander by one ring spacing unless the level says otherwise.
constexpr double kDefaultWoodTurbulence = 1.0;

const std::vector<std::pair<const char*, TexturePattern>>& PatternNames() {
  static const std::vector<std::pair<const char*, TexturePattern>> names = {{"solid", TexturePattern::kSolid},
                                                                            {"checker", TexturePattern::kChecker},
                                                                            {"stripes", TexturePattern::kStripes},
                                                                            {"noise", TexturePattern::kNoise},
                                                                            {"wood", TexturePattern::kWood}};
  return names;
}

TexturePattern ReadPattern(const YamlValue& value) {
  const std::string name = value.AsString();
  std::string known;
  for (const auto& [pattern_name, pattern] : PatternNames()) {
    if (name == pattern_name) return pattern;
    known += std::string(known.empty() ? "" : ", ") + pattern_name;
  }
  value.Fail("unknown pattern " + value.Text() + " (patterns: " + known + ")");
}

// A key the pattern does not use is refused rather than silently ignored.
void RefuseUnused(const YamlValue& surface, const char* key, const std::string& pattern) {
  if (const auto value = surface.Optional(key)) value->Fail("a " + pattern + " texture has no " + key);
}

// `colours`: `random`, or `count` colours, each three numbers in [0, 1].
void ReadColours(const YamlValue& value, std::size_t count, SurfaceTextureEntry* entry) {
  if (!value.IsSequence()) {
    if (value.AsString() != "random") value.Fail("expected a list of colours or 'random', got " + value.Text());
    entry->texture.random_colours = true;
    entry->settings["colours"] = "random";
    return;
  }
  const std::vector<YamlValue> colours = value.Elements();
  if (colours.size() != count) {
    value.Fail("expected " + std::to_string(count) + (count == 1 ? " colour" : " colours") + " [r, g, b], got " +
               value.Text());
  }
  const Range unit{0.0, 1.0, false, "", "linear reflectance"};
  nlohmann::ordered_json recorded = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < colours.size(); ++i) {
    const Vec3 rgb = colours[i].AsVec3(unit);
    (i == 0 ? entry->texture.colour_a : entry->texture.colour_b) = rgb.cast<float>();
    recorded.push_back({rgb.x(), rgb.y(), rgb.z()});
  }
  if (count == 1) entry->texture.colour_b = entry->texture.colour_a;
  entry->settings["colours"] = recorded;
}

}  // namespace

SurfaceTextureEntry ReadSurfaceTexture(const YamlValue& value) {
  SurfaceTextureEntry entry;
  const YamlValue pattern_value = value.Required("pattern");
  const std::string pattern_name = pattern_value.AsString();
  entry.texture.pattern = ReadPattern(pattern_value);
  entry.settings["pattern"] = pattern_name;
  const bool solid = entry.texture.pattern == TexturePattern::kSolid;
  const bool wood = entry.texture.pattern == TexturePattern::kWood;
  if (solid) {
    RefuseUnused(value, "scale_m", pattern_name);
    RefuseUnused(value, "angle_deg", pattern_name);
  } else {
    entry.texture.scale_m = value.Double("scale_m", Range{0.001, 100.0, false, "m"});
    entry.settings["scale_m"] = entry.texture.scale_m;
  }
  ReadColours(value.Required("colours"), solid ? 1 : 2, &entry);
  if (!solid) {
    if (const auto angle = value.Optional("angle_deg")) {
      entry.texture.angle_deg = angle->AsDouble(Range{-180.0, 180.0, false, "degrees"});
      entry.settings["angle_deg"] = entry.texture.angle_deg;
    }
  }
  if (!wood) {
    RefuseUnused(value, "turbulence", pattern_name);
  } else {
    const auto turbulence = value.Optional("turbulence");
    entry.texture.turbulence =
        turbulence ? turbulence->AsDouble(Range{0.0, 8.0, false, "ring spacings"}) : kDefaultWoodTurbulence;
    entry.settings["turbulence"] = entry.texture.turbulence;
  }
  value.ExpectNoOtherKeys();
  return entry;
}

}  // namespace tavis::batch::perturb
