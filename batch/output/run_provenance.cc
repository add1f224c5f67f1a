#include "batch/output/run_provenance.h"

#include <fstream>
#include <thread>

#include "batch/output/program_version.h"
#include "batch/output/sha256.h"

namespace tavis::batch::output {
namespace {

std::string CpuModel() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("model name", 0) != 0) continue;
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    const std::size_t start = line.find_first_not_of(" \t", colon + 1);
    if (start != std::string::npos) return line.substr(start);
  }
  return "unknown";
}

}  // namespace

nlohmann::json ProgramProvenanceJson() { return {{"version", ProgramVersion()}, {"git_revision", ProgramRevision()}}; }

nlohmann::json MachineJson(int threads_used) {
  return {{"cpu_model", CpuModel()},
          {"hardware_threads", std::thread::hardware_concurrency()},
          {"threads_used", threads_used}};
}

nlohmann::json ConfigFilesJson(const std::vector<ConfigFile>& files) {
  nlohmann::json json = nlohmann::json::object();
  for (const auto& [role, path] : files)
    json[role] = {{"file", path.filename().string()}, {"sha256", FileSha256(path)}};
  return json;
}

}  // namespace tavis::batch::output
