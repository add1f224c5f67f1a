// A served cell and the contract its policy server declares at connect (remote/server_contract.h):
// read before the cell is planned, then adopted by the plan as `--match-dataset`'s layout is (the
// request's cameras, keys and image size, and the executed steps as replan_steps), so that a
// server that says what its policy was trained on is served exactly that with no option. A
// setting given that contradicts it is refused before anything runs, naming both values.
#pragma once

#include <optional>

#include "batch/cell/cell_settings.h"
#include "batch/remote/observation_keys.h"
#include "batch/remote/server_contract.h"

namespace tavis::batch::cell {

// The contract the cell's first server declares (nullopt: not a served cell, or a server that
// declares none). Waits for the server as the cell would (server_ready_timeout_s). Throws
// std::runtime_error naming the server when it cannot be reached, std::invalid_argument when its
// contract is malformed.
std::optional<remote::ServerContract> ReadDeclaredContract(const EvaluationCellConfig& config);

// The layout of a cell whose config.declared_contract is set: the contract's, with
// config.replan_steps set to its executed steps. Throws std::invalid_argument naming both values
// when the contract says its policy was trained for another task or robot than the cell's
// (before anything else is compared), output::SettingError naming
// observation_keys, observation_dataset (`dataset`, the named dataset's layout), image_width or
// replan_steps when one given contradicts the contract (its value and the contract's), and
// std::invalid_argument when the robot's observation.state is not `state_size` long as declared.
remote::ObservationKeys AdoptDeclaredContract(EvaluationCellConfig& config,
                                              const std::optional<remote::ObservationKeys>& dataset, int state_size);

}  // namespace tavis::batch::cell
