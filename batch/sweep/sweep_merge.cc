#include "batch/sweep/sweep_merge.h"

#include <algorithm>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <vector>

#include "batch/cell/cell_record_stream.h"
#include "batch/output/atomic_file.h"
#include "batch/output/output_folder.h"
#include "batch/output/settings_difference.h"
#include "batch/sweep/sequential_plan.h"
#include "batch/sweep/sweep_cell.h"
#include "batch/sweep/sweep_manifest.h"
#include "batch/sweep/sweep_results.h"
#include "batch/sweep/sweep_spec.h"

namespace tavis::batch::sweep {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

// The settings shards must share, flattened for output::SettingsDifference ("/spec/episodes 6 -> 5").
nlohmann::json SweepIdentity(const Json& manifest) {
  return nlohmann::json::parse(
      Json{{"spec", manifest["spec"]}, {"version", manifest["version"]}, {"shard count", manifest["shard"]["count"]}}
          .flatten()
          .dump());
}

// Merging into a shard's folder (or below it) would copy the shard into itself, level after level.
void RequireOutsideShards(const std::vector<std::string>& shard_dirs, const std::string& out_dir) {
  const fs::path out = fs::weakly_canonical(fs::absolute(out_dir));
  for (const std::string& dir : shard_dirs) {
    const fs::path shard = fs::weakly_canonical(fs::absolute(dir));
    const auto [shard_end, out_at] = std::mismatch(shard.begin(), shard.end(), out.begin(), out.end());
    if (shard_end == shard.end()) {
      throw std::invalid_argument("--out " + out_dir + (out_at == out.end() ? " is" : " is inside") +
                                  " the shard folder " + dir + ": merge into a folder outside every shard");
    }
  }
}

// The cells of `shards` each complete with the settings this merge expects (`cell_jsons`); else
// the first problem, named: a complete cell run with other settings (another robot file, program
// version or --config-dir) is named with the keys that differ and a shard whose cells have the
// expected ones; a cell not complete is to be finished by rerunning its shard.
void RequireCompleteCells(const std::vector<SweepCell>& cells, const std::vector<nlohmann::json>& cell_jsons,
                          const std::vector<std::string>& shards, const std::vector<std::size_t>& shard_position,
                          const std::string& config_dir) {
  const std::size_t count = shards.size();
  std::vector<bool> shard_as_expected(count, false);  // some cell of the shard has the expected settings
  std::string other_settings, not_complete;
  std::size_t other_shard = 0;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::size_t shard = shard_position[i] % count;
    const fs::path from = fs::path(shards[shard]) / "cells" / cells[i].id;
    if (ReadCompleteCell(from, cell_jsons[i], cells[i].config.episodes)) {
      shard_as_expected[shard] = true;
      continue;
    }
    const std::optional<nlohmann::json> recorded = ReadCellSettings(from);
    if (recorded && ReadCompleteCell(from, *recorded, cells[i].config.episodes)) {
      if (other_settings.empty()) {
        other_settings = "cell " + cells[i].id + " of shard " + shards[shard] +
                         " is complete but ran with other settings (its cell.json -> this merge's spec and "
                         "--config-dir " +
                         config_dir + "): " + output::SettingsDifference(*recorded, cell_jsons[i]);
        other_shard = shard;
      }
    } else if (not_complete.empty()) {
      not_complete = from.string() + " is not complete: rerun shard " + shards[shard] + " (it resumes) before merging";
    }
  }
  if (!other_settings.empty()) {
    for (std::size_t s = 0; s < count; ++s) {
      if (s == other_shard || !shard_as_expected[s]) continue;
      throw std::invalid_argument(other_settings + "; the cells of shard " + shards[s] +
                                  " have this merge's settings: every shard of a sweep must run with the same "
                                  "robot files and program version");
    }
    throw std::invalid_argument(other_settings +
                                "; no shard's cells have this merge's settings: give merge the "
                                "--config-dir the shards ran with");
  }
  if (!not_complete.empty()) throw std::invalid_argument(not_complete);
}

}  // namespace

void MergeSweeps(const std::vector<std::string>& shard_dirs, const std::string& out_dir,
                 const std::string& config_dir) {
  if (shard_dirs.empty()) throw std::invalid_argument("merge needs the shards' output folders");
  output::RequireUsableOutputPath(out_dir);
  RequireOutsideShards(shard_dirs, out_dir);
  std::vector<Json> manifests;
  for (const std::string& dir : shard_dirs) manifests.push_back(SweepManifest::Read(dir));
  const Json& first = manifests.front();
  const int count = first["shard"]["count"].get<int>();
  std::vector<std::string> shard_of(static_cast<std::size_t>(count));
  std::vector<const Json*> manifest_of(static_cast<std::size_t>(count), nullptr);
  for (std::size_t s = 0; s < manifests.size(); ++s) {
    const std::string difference = output::SettingsDifference(SweepIdentity(first), SweepIdentity(manifests[s]));
    if (!difference.empty()) {
      throw std::invalid_argument("shards of different sweeps: " + shard_dirs[s] + " differs from " +
                                  shard_dirs.front() + ": " + difference);
    }
    const int index = manifests[s]["shard"]["index"].get<int>();
    if (index < 0 || index >= count)
      throw std::invalid_argument(shard_dirs[s] + "/manifest.json: shard index " + std::to_string(index) +
                                  " out of range");
    if (!shard_of[index].empty())
      throw std::invalid_argument("shard " + std::to_string(index) + " given twice: " + shard_of[index] + " and " +
                                  shard_dirs[s]);
    shard_of[index] = shard_dirs[s];
    manifest_of[index] = &manifests[s];
  }
  std::string missing;
  for (int index = 0; index < count; ++index) {
    if (shard_of[index].empty())
      missing += (missing.empty() ? "" : ", ") + std::to_string(index) + "/" + std::to_string(count);
  }
  if (!missing.empty()) throw std::invalid_argument("merge needs every shard; missing " + missing);

  // The shards' cells are finished: the files their policies read need not be here.
  const SweepSpec spec =
      ParseSweepSpec(first["spec_yaml"].get<std::string>(), shard_dirs.front() + "/manifest.json spec_yaml", config_dir,
                     PolicyFiles::kNotRead);
  const std::vector<SweepCell> cells = ExpandCells(spec, config_dir);
  std::vector<nlohmann::json> cell_jsons;  // what each cell's cell.json must say, its files read once
  for (const SweepCell& cell : cells) cell_jsons.push_back(cell::CellSettingsJson(cell.config));
  // A sequential test's group of paired cells ran in the shard of its first cell.
  const std::vector<std::size_t> shard_position = PlanSequential(cells, spec.sequential).shard_position;
  RequireCompleteCells(cells, cell_jsons, shard_of, shard_position, config_dir);

  const fs::path out = out_dir;
  if (!output::HoldsNoResults(out))
    throw std::invalid_argument(out_dir + " already holds files; merge into a new folder");
  const output::OutputLock lock = output::CreateAndLockOutput(out, "sweep merge");
  if (!output::HoldsNoResults(out))
    throw std::invalid_argument(out_dir + " already holds files; merge into a new folder");
  // OUT stays an empty sweep folder until the merged one, built beside it, takes its place: a
  // merge that fails or is killed leaves nothing that stops the same command.
  output::WriteOutputMarker(out, output::OutputKind::kSweep);
  output::OutputReplacement merging(out, "sweep merge");
  const fs::path staging = merging.staging();
  output::WriteOutputMarker(staging, output::OutputKind::kSweep);
  fs::create_directories(staging / "cells");
  SweepManifest manifest(spec, first["spec_yaml"].get<std::string>(), Shard{0, 1}, {});
  Json merged = manifest.Json();
  merged["spec_file"] = first.value("spec_file", Json());
  merged["merged_from"] = Json::array();
  for (int index = 0; index < count; ++index) {
    merged["merged_from"].push_back({{"dir", shard_of[index]},
                                     {"machine", manifest_of[index]->value("machine", Json())},
                                     {"timing", manifest_of[index]->value("timing", Json())}});
  }
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const fs::path from =
        fs::path(shard_of[shard_position[i] % static_cast<std::size_t>(count)]) / "cells" / cells[i].id;
    fs::copy(from, staging / "cells" / cells[i].id, fs::copy_options::recursive);
    merged["cells"][cells[i].id] = "complete";
  }
  output::WriteFileAtomically(staging / "manifest.json", merged.dump(2) + "\n");
  WriteSweepResults(staging, SweepSpecJson(spec), cells, cell_jsons, merged);
  merging.SwapIn();
}

}  // namespace tavis::batch::sweep
