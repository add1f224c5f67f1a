#include "batch/sweep/sweep_merge.h"

#include <filesystem>
#include <stdexcept>
#include <vector>

#include "batch/cell/cell_record_stream.h"
#include "batch/output/atomic_file.h"
#include "batch/output/output_folder.h"
#include "batch/output/settings_difference.h"
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

}  // namespace

void MergeSweeps(const std::vector<std::string>& shard_dirs, const std::string& out_dir,
                 const std::string& config_dir) {
  if (shard_dirs.empty()) throw std::invalid_argument("merge needs the shards' output folders");
  output::RequireUsableOutputPath(out_dir);
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
  const fs::path out = out_dir;
  if (!output::HoldsNoResults(out))
    throw std::invalid_argument(out_dir + " already holds files; merge into a new folder");
  const output::OutputLock lock = output::CreateAndLockOutput(out, "sweep merge");
  if (!output::HoldsNoResults(out))
    throw std::invalid_argument(out_dir + " already holds files; merge into a new folder");
  output::WriteOutputMarker(out, output::OutputKind::kSweep);
  fs::create_directories(out / "cells");
  SweepManifest manifest(spec, first["spec_yaml"].get<std::string>(), Shard{0, 1}, {});
  Json merged = manifest.Json();
  merged["spec_file"] = first.value("spec_file", Json());
  merged["merged_from"] = Json::array();
  for (int index = 0; index < count; ++index) {
    merged["merged_from"].push_back({{"dir", shard_of[index]},
                                     {"machine", manifest_of[index]->value("machine", Json())},
                                     {"timing", manifest_of[index]->value("timing", Json())}});
  }
  std::vector<nlohmann::json> cell_jsons;  // what each cell's cell.json must say, its files read once
  for (std::size_t i = 0; i < cells.size(); ++i) {
    cell_jsons.push_back(cell::CellSettingsJson(cells[i].config));
    const fs::path from = fs::path(shard_of[i % static_cast<std::size_t>(count)]) / "cells" / cells[i].id;
    if (!ReadCompleteCell(from, cell_jsons.back(), cells[i].config.episodes)) {
      throw std::invalid_argument(from.string() + " is not complete: rerun that shard (it resumes) before merging");
    }
    fs::copy(from, out / "cells" / cells[i].id, fs::copy_options::recursive);
    merged["cells"][cells[i].id] = "complete";
  }
  output::WriteFileAtomically(out / "manifest.json", merged.dump(2) + "\n");
  WriteSweepResults(out, SweepSpecJson(spec), cells, cell_jsons, merged);
}

}  // namespace tavis::batch::sweep
