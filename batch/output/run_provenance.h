// Where a result came from, for the `provenance` section of a cell's summary.json and of a sweep's
// manifest.json: the program (version and full git revision), the hashes of the files it read, and
// the machine it ran on. The machine (and the times beside it) differ from run to run: a
// `provenance` section is never compared by a resume, a merge or `tavis verify` (docs/verifying.md).
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace tavis::batch::output {

// {"version": ProgramVersion(), "git_revision": ProgramRevision()}.
nlohmann::json ProgramProvenanceJson();

// {"cpu_model": the first "model name" of /proc/cpuinfo ("unknown" where it has none),
//  "hardware_threads": what the machine offers, "threads_used": `threads_used`}.
nlohmann::json MachineJson(int threads_used);

// A file read, by the role it played ("robot", "perturbations/lighting", "spec").
using ConfigFile = std::pair<std::string, std::filesystem::path>;
// {role: {"file": its name (not its folder: the record names no machine's path), "sha256":
// FileSha256}}. Throws std::invalid_argument naming a file that cannot be read.
nlohmann::json ConfigFilesJson(const std::vector<ConfigFile>& files);

}  // namespace tavis::batch::output
