#include "batch/sweep/sequential_stop.h"

#include <fstream>

#include "batch/output/atomic_file.h"

namespace tavis::batch::sweep {

void WriteSequentialStop(const std::filesystem::path& dir, const nlohmann::ordered_json& stop) {
  output::WriteFileAtomically(dir / "sequential.json", stop.dump(2) + "\n");
}

int64_t SequentialEpisodes(const std::filesystem::path& dir, int64_t cap) {
  std::ifstream in(dir / "sequential.json");
  if (!in) return cap;
  const nlohmann::json stop = nlohmann::json::parse(in, nullptr, false);
  if (!stop.is_object() || !stop.contains("stopped_at") || !stop["stopped_at"].is_number_integer()) return cap;
  const int64_t stopped_at = stop["stopped_at"].get<int64_t>();
  return stopped_at >= 0 && stopped_at <= cap ? stopped_at : cap;
}

}  // namespace tavis::batch::sweep
