// The one function that names a cell's folder, for `tavis eval` (its default --out, a suite's
// cells) and `tavis sweep` (cells/<id>). Both name a cell <task>_<robot>_<split>_<camera>_<label>_s<seed>;
// they have always differed in where a perturbed cell's levels go, and each keeps its form so that
// a resume finds the folders it wrote before: a sweep puts them in the label (".camera.fov-wide",
// the label its tables and reports key by), `tavis eval` after the seed ("_p-camera-fov-wide").
#pragma once

#include <string>

#include "batch/cell/cell_settings.h"

namespace tavis::batch::cell {

// Where a cell folder's name puts the cell's perturbation levels.
enum class PerturbationsIn {
  kLabel,  // <label>.AXIS.LEVEL..._s<seed> (tavis sweep)
  kTail,   // <label>_s<seed>_p-AXIS-LEVEL... (tavis eval)
};

// The folder name of the cell `config` under `label` (eval: the policy, a head-still expert's
// "expert-head-still"; a sweep: the policy's label). With `one_episode` (eval's --episode I) the
// name says "_ep<I>" after the seed, so that one episode never takes its full cell's place.
// Throws std::invalid_argument for a perturbation that is not AXIS:LEVEL of a known axis.
std::string CellFolderName(const EvaluationCellConfig& config, const std::string& label, PerturbationsIn where,
                           bool one_episode = false);

}  // namespace tavis::batch::cell
