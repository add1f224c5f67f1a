#include "tests/batch/dataset/pyav_video.h"

#include <chrono>
#include <cstdio>

#include "tests/support/child_process.h"

namespace tavis::batch::dataset::testing {

PyAvReport CheckVideoWithPyAv(const std::string& path, int fps, const std::vector<FrameQuery>& queries,
                              const std::string& scratch_dir) {
  std::vector<std::string> args = {path, std::to_string(fps)};
  std::vector<std::string> outputs;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    char from[40];
    std::snprintf(from, sizeof from, "%.17g", queries[i].from_timestamp);  // every digit the table holds
    outputs.push_back(scratch_dir + "/query_" + std::to_string(i) + ".rgb");
    std::remove(outputs.back().c_str());
    args.insert(args.end(), {from, std::to_string(queries[i].frame_index), outputs.back()});
  }
  tavis::testing::ChildProcess script(
      tavis::testing::kDebianPython,
      tavis::testing::ScriptArgs(std::string(TAVIS_TEST_DATA_DIR) + "/check_video.py", args),
      "is python3-av (PyAV 10) installed for /usr/bin/python3?");
  PyAvReport report;
  report.stream = nlohmann::json::parse(script.ReadAllOutput(std::chrono::seconds(60)));
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const bool found = report.stream["lookups"].at(i)["found"].get<bool>();
    report.frames.push_back(found ? std::optional<RgbFrame>(ReadBytes(outputs[i])) : std::nullopt);
  }
  return report;
}

}  // namespace tavis::batch::dataset::testing
