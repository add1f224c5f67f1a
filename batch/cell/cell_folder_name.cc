#include "batch/cell/cell_folder_name.h"

#include "batch/perturb/perturbation_catalog.h"

namespace tavis::batch::cell {

std::string CellFolderName(const EvaluationCellConfig& config, const std::string& label, PerturbationsIn where,
                           bool one_episode) {
  std::string tail = one_episode ? "_ep" + std::to_string(config.episode_start) : "";
  std::string labelled = label;
  if (where == PerturbationsIn::kLabel) {
    labelled += perturb::PerturbationLabelSuffix(config.perturbations);
  } else {
    for (const std::string& choice : config.perturbations) {
      const perturb::PerturbationChoice parsed = perturb::ParsePerturbationChoice(choice);
      tail += "_p-" + parsed.axis + "-" + parsed.level;
    }
  }
  return config.task + "_" + config.robot + "_" + scenarios::ToString(config.split) + "_" + ToString(config.camera) +
         "_" + labelled + "_s" + std::to_string(config.seed) + tail;
}

}  // namespace tavis::batch::cell
