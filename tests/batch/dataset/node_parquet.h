// The independent Parquet readers and writer of tests/js (hyparquet and DuckDB under Node),
// run as child processes. They need tests/js/node_modules: run .ci/install-deps.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>

namespace tavis::batch::dataset::testing {

// What tests/js/read_parquet.mjs prints for `path`: {"hyparquet": {...}, "duckdb": {...}}.
nlohmann::json ReadWithIndependentReaders(const std::string& path);

// The rows of one DuckDB query (tests/js/query_duckdb.mjs), e.g. over a glob of files.
nlohmann::json QueryWithDuckdb(const std::string& sql);

// Writes `path` with DuckDB (tests/js/write_parquet.mjs; its header comment gives the table):
// `parquet_version` "v1" or "v2", `row_group_size` 0 for DuckDB's default, `compression` as
// DuckDB names it ("snappy", "zstd", "uncompressed").
void WriteWithDuckdb(const std::string& path, std::size_t rows, const std::string& parquet_version,
                     std::size_t row_group_size, const std::string& compression = "snappy");

}  // namespace tavis::batch::dataset::testing
