#include "tests/batch/dataset/node_parquet.h"

#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "tests/support/child_process.h"

namespace tavis::batch::dataset::testing {
namespace {

constexpr const char* kHint =
    "the Parquet tests need Node with tests/js/node_modules (hyparquet, @duckdb/node-api): run .ci/install-deps";

std::string Script(const std::string& name) {
  const std::string js_dir = TAVIS_JS_DIR;
  if (!std::filesystem::exists(js_dir + "/node_modules/hyparquet") ||
      !std::filesystem::exists(js_dir + "/node_modules/@duckdb/node-api")) {
    throw std::runtime_error(js_dir + "/node_modules lacks hyparquet or @duckdb/node-api; " + kHint);
  }
  return js_dir + "/" + name;
}

std::string RunNode(const std::vector<std::string>& args) {
  tavis::testing::ChildProcess node(tavis::testing::kNode, args, kHint);
  return node.ReadAllOutput(std::chrono::seconds(60));
}

}  // namespace

nlohmann::json ReadWithIndependentReaders(const std::string& path) {
  const std::string output = RunNode({Script("read_parquet.mjs"), path});
  try {
    return nlohmann::json::parse(output);
  } catch (const nlohmann::json::parse_error& error) {
    throw std::runtime_error("read_parquet.mjs printed no JSON for " + path + ": " + error.what() + "\n" +
                             output.substr(0, 500));
  }
}

nlohmann::json QueryWithDuckdb(const std::string& sql) {
  const std::string output = RunNode({Script("query_duckdb.mjs"), sql});
  try {
    return nlohmann::json::parse(output);
  } catch (const nlohmann::json::parse_error& error) {
    throw std::runtime_error("query_duckdb.mjs printed no JSON for " + sql + ": " + error.what());
  }
}

void WriteWithDuckdb(const std::string& path, std::size_t rows, const std::string& parquet_version,
                     std::size_t row_group_size, const std::string& compression) {
  RunNode({Script("write_parquet.mjs"), path, std::to_string(rows), parquet_version, std::to_string(row_group_size),
           compression});
}

}  // namespace tavis::batch::dataset::testing
