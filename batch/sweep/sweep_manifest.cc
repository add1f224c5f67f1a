#include "batch/sweep/sweep_manifest.h"

#include <sys/utsname.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <ctime>
#include <fstream>
#include <stdexcept>
#include <thread>

#include "batch/output/atomic_file.h"
#include "batch/output/json_error_text.h"
#include "batch/output/program_version.h"
#include "batch/output/run_provenance.h"
#include "batch/output/settings_difference.h"
#include "batch/output/sha256.h"
#include "batch/output/utc_time.h"

namespace tavis::batch::sweep {
nlohmann::ordered_json MachineJson() {
  char host[256] = {};
  gethostname(host, sizeof(host) - 1);
  utsname system{};
  uname(&system);
  return {{"hostname", host},
          {"cores", std::thread::hardware_concurrency()},
          {"system", std::string(system.sysname) + " " + system.release + " " + system.machine}};
}

SweepManifest::SweepManifest(const SweepSpec& spec, const std::string& spec_yaml, const Shard& shard,
                             const std::vector<std::string>& cell_ids) {
  nlohmann::ordered_json cells = nlohmann::ordered_json::object();
  for (const std::string& id : cell_ids) cells[id] = "pending";
  json_ = {{"format", "tavis-sweep/1"},
           {"spec", SweepSpecJson(spec)},
           {"spec_file", spec.source},
           {"spec_yaml", spec_yaml},
           {"version", output::ProgramVersion()},
           {"machine", MachineJson()},
           {"shard", {{"index", shard.index}, {"count", shard.count}}},
           {"cells", cells},
           {"timing", {{"started", output::UtcNow()}, {"updated", output::UtcNow()}}},
           // Never compared by a resume or a merge (RequireSameSweep, sweep_merge.cc): how and where it ran.
           {"provenance",
            {{"program", output::ProgramProvenanceJson()},
             {"spec",
              {{"file", std::filesystem::path(spec.source).filename().string()},
               {"sha256", "sha256:" + output::Sha256Hex(spec_yaml)}}},
             {"machine", output::MachineJson(0)}}}};
}

nlohmann::ordered_json SweepManifest::Read(const std::filesystem::path& dir) {
  const std::filesystem::path path = dir / "manifest.json";
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot open file (not a sweep's output folder?)");
  nlohmann::ordered_json manifest;
  try {
    manifest = nlohmann::ordered_json::parse(in);
  } catch (const nlohmann::json::exception& error) {
    throw std::runtime_error(path.string() +
                             ": damaged sweep manifest, not valid JSON: " + output::JsonErrorText(error.what()));
  }
  if (!manifest.is_object()) throw std::runtime_error(path.string() + ": damaged sweep manifest, not a JSON object");
  for (const char* key : {"spec", "spec_yaml", "version", "shard", "cells"}) {
    if (!manifest.contains(key)) throw std::runtime_error(path.string() + ": missing key '" + key + "'");
  }
  // The keys resumes and merges read, each of the type this program writes.
  const auto require = [&](bool ok, const char* key, const char* what) {
    if (!ok) {
      throw std::runtime_error(path.string() + ": damaged sweep manifest, '" + key + "' must be " + what + ", got " +
                               manifest[key].dump().substr(0, 80));
    }
  };
  require(manifest["spec"].is_object(), "spec", "an object");
  require(manifest["spec_yaml"].is_string(), "spec_yaml", "a string");
  require(manifest["version"].is_string(), "version", "a string");
  require(manifest["cells"].is_object(), "cells", "an object of cell ids");
  const nlohmann::ordered_json& shard = manifest["shard"];
  require(shard.is_object() && shard.contains("index") && shard.contains("count") &&
              shard["index"].is_number_integer() && shard["count"].is_number_integer() &&
              shard["count"].get<int64_t>() >= 1 && shard["index"].get<int64_t>() >= 0 &&
              shard["index"].get<int64_t>() < shard["count"].get<int64_t>() && shard["count"].get<int64_t>() <= 1000000,
          "shard", "{\"index\": I, \"count\": N} with 0 <= I < N");
  return manifest;
}

void SweepManifest::RequireSameSweep(const nlohmann::ordered_json& existing, const std::filesystem::path& dir) const {
  const auto compared = [](const nlohmann::ordered_json& manifest) {
    return nlohmann::json::parse(nlohmann::ordered_json{
        {"spec", manifest["spec"]}, {"version", manifest["version"]}, {"shard", manifest["shard"]}}
                                     .flatten()
                                     .dump());
  };
  const nlohmann::json was = compared(existing);
  const nlohmann::json now = compared(json_);
  const std::string difference = output::SettingsDifference(was, now);
  if (!difference.empty()) {
    throw std::invalid_argument(dir.string() + " holds another sweep (" + difference +
                                "); write the sweep to another folder, or remove this one to start over");
  }
}

void SweepManifest::SetState(const std::string& cell_id, const std::string& state) {
  std::lock_guard<std::mutex> lock(mutex_);
  json_["cells"][cell_id] = state;
  json_["timing"]["updated"] = output::UtcNow();
}

void SweepManifest::SetTiming(double wall_s, int threads, int jobs) {
  std::lock_guard<std::mutex> lock(mutex_);
  json_["timing"]["wall_s"] = wall_s;
  json_["timing"]["threads"] = threads;
  json_["timing"]["concurrent_cells"] = jobs;
  json_["provenance"]["machine"]["threads_used"] = threads;
  json_["timing"]["updated"] = output::UtcNow();
}

nlohmann::ordered_json SweepManifest::Json() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return json_;
}

void SweepManifest::Write(const std::filesystem::path& dir) const {
  std::lock_guard<std::mutex> lock(mutex_);
  output::WriteFileAtomically(dir / "manifest.json", json_.dump(2) + "\n");
}

}  // namespace tavis::batch::sweep
