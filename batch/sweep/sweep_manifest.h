// DIR/manifest.json of a sweep: the spec (its settings and its text), the program version (git
// describe at build time), the machine, the shard, each cell's state (pending, interrupted,
// running, complete) and its provenance (the program's full git revision, the spec text's sha256,
// the CPU model and threads: batch/output/run_provenance.h). Rewritten atomically on every change, so a reader sees one
// whole version.
#pragma once

#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/sweep/sweep_spec.h"

namespace tavis::batch::sweep {

// hostname, cores and the kernel (uname), for telling runs apart.
nlohmann::ordered_json MachineJson();

// The keys merge compares: spec, version, shard count. The spec's YAML text travels along so that
// `tavis sweep merge` can expand the cells without the file.
class SweepManifest {
 public:
  SweepManifest(const SweepSpec& spec, const std::string& spec_yaml, const Shard& shard,
                const std::vector<std::string>& cell_ids);

  // Reads DIR/manifest.json; throws std::runtime_error naming the file when it is not one.
  static nlohmann::ordered_json Read(const std::filesystem::path& dir);

  // Throws std::invalid_argument naming DIR and what differs when DIR's manifest is of another
  // spec, program version or shard.
  void RequireSameSweep(const nlohmann::ordered_json& existing, const std::filesystem::path& dir) const;

  void SetState(const std::string& cell_id, const std::string& state);
  void SetTiming(double wall_s, int threads, int jobs);
  nlohmann::ordered_json Json() const;
  void Write(const std::filesystem::path& dir) const;  // DIR/manifest.json

 private:
  mutable std::mutex mutex_;
  nlohmann::ordered_json json_;
};

}  // namespace tavis::batch::sweep
