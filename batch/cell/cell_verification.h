// Verifying a cell's records (`tavis verify`): every episode of a cell that saved its actions
// (DIR/actions/episode_<i>.csv.gz, or the plain .csv older cells saved: a served cell, an expert
// cell at expert_hz 20) is re-simulated
// from them with the settings its cell.json records, in memory (nothing is written anywhere), and
// its record compared field by field with its line of episodes.jsonl; what the re-simulation reads
// now (the robot file, the perturbation levels' settings, the program) is compared with what
// cell.json recorded of them (its identity and levels).
#pragma once

#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/episode_driver.h"

namespace tavis::batch::cell {

// The folders holding a cell (a cell.json) under `dir`, at any depth, `dir` itself if it is one,
// in path order; a cell's own subfolders and hidden folders (an --overwrite's copy being built)
// are not searched. Throws std::invalid_argument when `dir` is not a folder.
std::vector<std::filesystem::path> FindCells(const std::filesystem::path& dir);

// The fields of an episodes.jsonl line compared, in the order a difference is named; a field
// outside this list that either side has is compared after them. Every field of the line is
// compared: none holds a time or anything else that may differ between two runs.
const std::vector<std::string>& VerifiedEpisodeFields();

// A value that differs: in an episode's record or (episode -1) in what the cell's settings were
// read from.
struct ValueDifference {
  int64_t episode = -1;
  std::string field;     // "success", "stage_ticks.target_grasped", "identity.robot_config.actuators.arm.position_gain"
  std::string recorded;  // as the record writes it (strings unquoted), "absent" where it has none
  std::string now;       // re-simulated, or read now
};

enum class VerifyOutcome { kIdentical, kDiffers, kNoActions };

struct CellVerification {
  std::filesystem::path cell;
  VerifyOutcome outcome = VerifyOutcome::kIdentical;
  std::string no_actions;  // kNoActions: why the cell has none ("policy 'expert' at expert_hz 60 saves none")
  bool complete = true;    // it has summary.json; an interrupted cell's complete records are verified
  int64_t episodes = 0;    // the episodes compared
  int64_t identical = 0;   // of them, the same in every field
  std::vector<ValueDifference> identity;  // the settings' sources that differ (each fails the cell)
  std::vector<ValueDifference> records;   // every differing field of every episode, in episode order
  // The program that wrote the cell and this one: a difference is reported but is no failure.
  std::string program_version_recorded;
  std::string program_version_now;
  // Fields this version writes that the records of an older one lack (not compared).
  std::set<std::string> fields_not_recorded;

  bool program_version_differs() const { return program_version_recorded != program_version_now; }
};

struct VerifySettings {
  std::string config_dir;     // where robots/ and perturbations/ are read now
  ProgressCallback progress;  // the cell's episodes re-simulated so far, of its total
};

// The records episodes.jsonl holds (its complete lines), without reading anything else: a
// progress total. Throws nothing; 0 when it has none.
int64_t RecordedEpisodeCount(const std::filesystem::path& cell);

// Verifies one cell. Throws std::invalid_argument naming the file when the cell cannot be read
// (cell.json or a line of episodes.jsonl not valid JSON, a setting of the wrong type, a missing or
// malformed action file, a robot or level no longer there).
CellVerification VerifyCell(const std::filesystem::path& cell, const VerifySettings& settings);

// The cell's line, named `name`: "ok   NAME: 96/96 episodes identical", "FAIL NAME: episode 17
// field success: true recorded, false re-simulated; 95/96 episodes identical", "skip NAME: cannot
// verify: no actions (...)".
std::string VerificationLine(const CellVerification& verification, const std::string& name);

// The verification as JSON (`tavis verify --json`): the outcome, the counts and every difference.
nlohmann::json VerificationJson(const CellVerification& verification, const std::string& name);

}  // namespace tavis::batch::cell
