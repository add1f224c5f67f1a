#include "batch/perturb/prompt_paraphrase.h"

#include <vector>

namespace tavis::batch::perturb {

std::string EpisodePrompt(const engine::WorldModel& model, const scenarios::ScenarioDef& scenario,
                          const engine::BatchState& state, int env) {
  const engine::EpisodePerturbation& perturbation = model.episode_perturbation;
  if (!perturbation.paraphrases_prompt()) return scenario.prompt != nullptr ? scenario.prompt(state, env) : "";
  const auto paraphrases = perturbation.language.paraphrases.find(scenario.name);
  // The level, or else the task itself, gives every task of the registry some (episode_perturbation_levels.cc).
  TAVIS_INVARIANT(paraphrases != perturbation.language.paraphrases.end() && !paraphrases->second.empty(),
                  "a language level has paraphrases for every task");
  engine::RandomStream rng(perturbation.seed, engine::RandomStreamId::kParaphrase,
                           static_cast<uint64_t>(state.episode[static_cast<std::size_t>(env)]));
  const std::vector<std::string>& choices = paraphrases->second;
  std::string prompt = choices[static_cast<std::size_t>(rng.UniformInt(static_cast<int>(choices.size())))];
  const std::string placeholder = "{object}";
  const std::size_t at = prompt.find(placeholder);
  if (at == std::string::npos) return prompt;
  const std::string& target = model.objects[static_cast<std::size_t>(state.target(env))].name;
  const auto name = perturbation.language.object_names.find(target);
  // A level that says {object} names every catalog object, and only those are targets.
  TAVIS_INVARIANT(name != perturbation.language.object_names.end(), "the language level names the target");
  for (std::size_t from = at; from != std::string::npos; from = prompt.find(placeholder, from + name->second.size()))
    prompt.replace(from, placeholder.size(), name->second);
  return prompt;
}

}  // namespace tavis::batch::perturb
