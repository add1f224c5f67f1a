// Commanded-action trajectories as CSV files: the input of `tavis galt` and `--policy replay`,
// and what a served policy's episodes are saved as.
//
// Format: one row per step, `columns` comma-separated decimal numbers (19 for the canonical
// action, reference spec section 5). An optional header row is allowed as the first line: it is
// a header when none of its fields is a number. Blank lines are skipped, whitespace around
// fields and a trailing '\r' are ignored. Every value must be finite.
#pragma once

#include <filesystem>
#include <istream>
#include <string>
#include <vector>

#include "kinematics/action.h"
#include "kinematics/galt.h"

namespace tavis::batch {

struct ActionTrajectory {
  std::vector<double> values;  // (num_steps x num_columns), row-major
  int num_steps = 0;
  int num_columns = 0;

  kinematics::TrajectoryView view() const { return {values.data(), num_steps, num_columns}; }
};

// Parses CSV text; `source` names the input in error messages. Throws std::runtime_error
// "SOURCE:LINE: what is wrong" on a wrong column count, a non-numeric or non-finite value, and
// "SOURCE: no data rows" when there are none.
ActionTrajectory ParseActionCsv(std::istream& in, const std::string& source, int columns = kinematics::action::kSize);

// Reads and parses a file; a file that cannot be opened throws "FILE: cannot open ...".
ActionTrajectory ReadActionCsv(const std::filesystem::path& path, int columns = kinematics::action::kSize);

// Writes one row per action, each value in the shortest form that reads back to the same double,
// so ReadActionCsv returns the actions bit-exactly. Throws std::runtime_error "FILE: cannot
// write" when the file cannot be written.
void WriteActionCsv(const std::filesystem::path& path, const std::vector<kinematics::Action>& rows);

}  // namespace tavis::batch
