// Commanded-action trajectories as CSV files: the input of `tavis galt` and `--policy replay`,
// and what a served policy's episodes are saved as (gzip-compressed: DIR/actions/episode_<i>.csv.gz).
//
// Format: one row per step, `columns` comma-separated decimal numbers (19 for the canonical
// action, reference spec section 5). An optional header row is allowed as the first line: it is
// a header when none of its fields is a number. Blank lines are skipped, whitespace around
// fields and a trailing '\r' are ignored. Every value must be finite.
#pragma once

#include <cstdint>
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

// Reads and parses a file, plain or gzip-compressed (told by its bytes, not its name); a file that
// cannot be opened throws "FILE: cannot open ...", damaged gzip data "FILE: damaged gzip data: ...".
ActionTrajectory ReadActionCsv(const std::filesystem::path& path, int columns = kinematics::action::kSize);

enum class ActionFileFormat { kPlain, kGzip };

// Writes one row per action, each value in the shortest form that reads back to the same double,
// so ReadActionCsv returns the actions bit-exactly; kGzip compresses it (a gzip stream without a
// time stamp: the same actions give the same bytes). Throws std::runtime_error "FILE: cannot
// write" when the file cannot be written.
void WriteActionCsv(const std::filesystem::path& path, const std::vector<kinematics::Action>& rows,
                    ActionFileFormat format = ActionFileFormat::kPlain);

// The name a cell saves episode i's actions under: "episode_<i>.csv.gz".
std::string EpisodeActionsName(int64_t episode);
// Episode i's actions in a folder of them (a cell's DIR/actions): episode_<i>.csv as older cells
// saved them, else episode_<i>.csv.gz; empty when it has neither.
std::filesystem::path FindEpisodeActions(const std::filesystem::path& folder, int64_t episode);

}  // namespace tavis::batch
