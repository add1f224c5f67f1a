#include "batch/perturb/episode_perturbation_levels.h"

#include <algorithm>
#include <map>
#include <optional>
#include <vector>

#include "engine/object_catalog.h"
#include "scenarios/registry.h"

namespace tavis::batch::perturb {
namespace {

using configs::Range;
using configs::YamlValue;

constexpr const char* kObjectPlaceholder = "{object}";

// Distractor object names become parts of the world's object names.
void CheckObjectName(const YamlValue& name_value, const std::string& name) {
  const bool plain = std::all_of(name.begin(), name.end(), [](unsigned char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
  });
  if (name.empty() || name.size() > 32 || !plain) {
    name_value.Fail("an object name must be 1 to 32 lower-case letters, digits, '-' or '_', got " + name_value.Text());
  }
}

// One object of the distractors file's `objects:` list.
engine::DistractorKind ReadDistractorKind(const YamlValue& entry, nlohmann::ordered_json* settings) {
  engine::DistractorKind kind;
  const YamlValue name = entry.Required("name");
  kind.name = name.AsString();
  CheckObjectName(name, kind.name);
  const YamlValue shape = entry.Required("shape");
  const std::string shape_name = shape.AsString();
  if (shape_name == "box") {
    kind.shape.kind = ShapeKind::kBox;
  } else if (shape_name == "cylinder") {
    kind.shape.kind = ShapeKind::kCylinder;
  } else if (shape_name == "sphere") {
    kind.shape.kind = ShapeKind::kSphere;
  } else {
    shape.Fail("must be box, cylinder or sphere, got " + shape.Text());
  }
  // Sizes as kinematics/shape.h gives them; small enough to stand in every task's distractor zone.
  const YamlValue size = entry.Required("size_m");
  kind.shape.size = size.AsVec3({0.01, 0.15, false, "m"});
  const Vec3& s = kind.shape.size;
  if (kind.shape.kind == ShapeKind::kCylinder && s.x() != s.y())
    size.Fail("a cylinder's size is [radius, radius, height], got " + size.Text());
  if (kind.shape.kind == ShapeKind::kSphere && (s.x() != s.y() || s.x() != s.z()))
    size.Fail("a sphere's size is [radius, radius, radius], got " + size.Text());
  kind.mass_kg = entry.Double("mass_kg", {0.0, 5.0, true, "kg"});
  kind.rgb = entry.Vector3("rgb", {0.0, 1.0, false, "", "(linear reflectance)"});
  entry.ExpectNoOtherKeys();
  *settings = {{"name", kind.name},
               {"shape", shape_name},
               {"size_m", {s.x(), s.y(), s.z()}},
               {"mass_kg", kind.mass_kg},
               {"rgb", {kind.rgb.x(), kind.rgb.y(), kind.rgb.z()}}};
  return kind;
}

// distractors: `count` objects drawn per episode from the file's `objects:`.
void ReadDistractorLevel(const YamlValue& file, const YamlValue& level, engine::EpisodePerturbation* effect,
                         nlohmann::ordered_json* settings) {
  const YamlValue objects = file.Required("objects");
  if (!objects.IsSequence() || objects.Elements().empty())
    objects.Fail("must be a non-empty list of objects, got " + objects.Text());
  engine::DistractorSettings& distractors = effect->distractors;
  nlohmann::ordered_json object_settings = nlohmann::ordered_json::array();
  for (const YamlValue& entry : objects.Elements()) {
    nlohmann::ordered_json one;
    engine::DistractorKind kind = ReadDistractorKind(entry, &one);
    for (const engine::DistractorKind& other : distractors.kinds) {
      if (other.name == kind.name) entry.Required("name").Fail("object '" + kind.name + "' is declared twice");
    }
    distractors.kinds.push_back(std::move(kind));
    object_settings.push_back(std::move(one));
  }
  const YamlValue count = level.Required("count");
  distractors.count = count.AsInt();
  const int declared = static_cast<int>(distractors.kinds.size());
  if (distractors.count < 1 || distractors.count > declared) {
    count.Fail("must be 1 to " + std::to_string(declared) + " (the objects the file declares), got " + count.Text());
  }
  (*settings)["count"] = distractors.count;
  (*settings)["objects"] = object_settings;
}

// A paraphrase is plain text, "{object}" its only placeholder: what is wrong with `text`, or "".
std::string ParaphraseDefect(const std::string& text) {
  if (text.empty() || text.size() > 500) return "a paraphrase must be 1 to 500 characters";
  std::string rest = text;
  for (std::size_t at = rest.find(kObjectPlaceholder); at != std::string::npos; at = rest.find(kObjectPlaceholder))
    rest.erase(at, std::string(kObjectPlaceholder).size());
  if (rest.find_first_of("{}") != std::string::npos) return "a paraphrase's only placeholder is {object}";
  return "";
}

// The task's own paraphrases for the level named `level` (scenario.h), or null.
const std::vector<std::string>* DeclaredParaphrases(const scenarios::ScenarioDef& scenario, const std::string& level) {
  for (const scenarios::LevelParaphrases& declared : scenario.paraphrases) {
    if (declared.level == level) return &declared.texts;
  }
  return nullptr;
}

// The names "{object}" stands for: every object a task can make its target must have one.
std::map<std::string, std::string> ReadObjectNames(const YamlValue& names, nlohmann::ordered_json* settings) {
  std::map<std::string, std::string> read;
  for (const std::string& object : engine::CatalogObjectNames()) {
    const YamlValue name = names.Required(object);
    read[object] = name.AsString();
    if (read[object].empty()) name.Fail("must name the object, got an empty name");
    (*settings)[object] = read[object];
  }
  names.ExpectNoOtherKeys();
  return read;
}

// language: per task (every task of the registry) its paraphrases: the level's `prompts` list for
// the task, else the task's own for the level's name (ScenarioDef::paraphrases), so a task's
// paraphrases live with the task; the level's object_names, or else the file's, for "{object}".
void ReadLanguageLevel(const YamlValue& file, const YamlValue& level, engine::EpisodePerturbation* effect,
                       nlohmann::ordered_json* settings) {
  engine::LanguageSettings& language = effect->language;
  const std::string level_name = level.String("name");
  const std::optional<YamlValue> prompts = level.Optional("prompts");
  nlohmann::ordered_json prompt_settings;
  std::optional<YamlValue> names_an_object;  // the level's first paraphrase that says {object}
  std::string declared_names_an_object;      // else the first task whose own paraphrase does
  for (const scenarios::ScenarioDef& scenario : scenarios::AllScenarios()) {
    std::vector<std::string>& texts = language.paraphrases[scenario.name];
    const std::optional<YamlValue> list = prompts ? prompts->Optional(scenario.name) : std::nullopt;
    if (list) {
      if (!list->IsSequence() || list->Elements().empty())
        list->Fail("must be a non-empty list of paraphrases, got " + list->Text());
      for (const YamlValue& item : list->Elements()) {
        texts.push_back(item.AsString());
        const std::string defect = ParaphraseDefect(texts.back());
        if (!defect.empty()) item.Fail(defect + ", got " + item.Text());
        if (texts.back().find(kObjectPlaceholder) != std::string::npos && !names_an_object) names_an_object = item;
      }
    } else {
      const std::vector<std::string>* declared = DeclaredParaphrases(scenario, level_name);
      if (declared == nullptr || declared->empty()) {
        level.Fail("gives task '" + scenario.name + "' no paraphrases (prompts." + scenario.name +
                   "), and the task declares none for level '" + level_name + "'");
      }
      for (const std::string& text : *declared) {
        const std::string defect = ParaphraseDefect(text);
        if (!defect.empty()) {
          level.Fail("task '" + scenario.name + "' declares for level '" + level_name + "' the paraphrase \"" + text +
                     "\": " + defect);
        }
        if (text.find(kObjectPlaceholder) != std::string::npos && declared_names_an_object.empty())
          declared_names_an_object = scenario.name;
        texts.push_back(text);
      }
    }
    prompt_settings[scenario.name] = texts;
  }
  if (prompts) prompts->ExpectNoOtherKeys();
  (*settings)["prompts"] = prompt_settings;
  const std::optional<YamlValue> file_names = file.Optional("object_names");
  const std::optional<YamlValue> level_names = level.Optional("object_names");
  const std::optional<YamlValue>& names = level_names ? level_names : file_names;
  if (names) {
    nlohmann::ordered_json name_settings;
    language.object_names = ReadObjectNames(*names, &name_settings);
    (*settings)["object_names"] = name_settings;
  } else if (names_an_object) {
    names_an_object->Fail("says {object}, but neither the level nor the file gives object_names");
  } else if (!declared_names_an_object.empty()) {
    level.Fail("task '" + declared_names_an_object +
               "' has a paraphrase for it that says {object}, but neither the level nor the file gives object_names");
  }
}

// runtime: the target moved distance_m when a hand first comes within trigger_m of it.
void ReadRuntimeLevel(const YamlValue&, const YamlValue& level, engine::EpisodePerturbation* effect,
                      nlohmann::ordered_json* settings) {
  engine::TargetMoveSettings& move = effect->target_move;
  move.trigger_m = level.Double("trigger_m", {0.0, 0.5, true, "m"});
  move.distance_m = level.Double("distance_m", {0.0, 0.3, true, "m"});
  (*settings)["trigger_m"] = move.trigger_m;
  (*settings)["distance_m"] = move.distance_m;
}

}  // namespace

EpisodeLevelReader FindEpisodeLevelReader(const std::string& axis) {
  static const std::map<std::string, EpisodeLevelReader> readers = {
      {"distractors", &ReadDistractorLevel},
      {"language", &ReadLanguageLevel},
      {"runtime", &ReadRuntimeLevel},
  };
  const auto reader = readers.find(axis);
  return reader == readers.end() ? nullptr : reader->second;
}

}  // namespace tavis::batch::perturb
