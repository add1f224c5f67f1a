// Reads columns of a Parquet file: the files our writer makes and those of pyarrow and DuckDB
// (LeRobot datasets as released). Supported:
// - data pages v1 and v2, with RLE/bit-packed hybrid levels;
// - values PLAIN, dictionary (PLAIN_DICTIONARY / RLE_DICTIONARY), DELTA_BINARY_PACKED,
//   DELTA_LENGTH_BYTE_ARRAY, BYTE_STREAM_SPLIT;
// - codecs UNCOMPRESSED, SNAPPY and ZSTD (others: "unsupported codec GZIP in column X of FILE");
// - physical types BOOLEAN, INT32, INT64, FLOAT, DOUBLE, BYTE_ARRAY;
// - scalar columns, and list columns at any nesting depth (read as the flat leaves of each row).
//
// A column is named by its top-level field (e.g. "action", "stats/action/mean"). Every problem
// throws std::runtime_error naming the file and what is wrong (bad magic, footer beyond the file,
// page past the end of its chunk, unsupported codec or encoding, nulls in a scalar column...).
// Every length read from the file is bounded by the file's size before anything is allocated.
//
//   ParquetReader reader(path);
//   std::vector<std::int64_t> episodes = reader.ReadColumn<std::int64_t>("episode_index");
//   ListColumn<float> actions = reader.ReadListColumn<float>("action");
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "batch/dataset/parquet/parquet_schema.h"

namespace tavis::batch::dataset::parquet {

struct FileMetadata;

// A list column: the leaves of all rows, row after row, and how many belong to each row (0 for a
// null or empty list).
template <typename T>
struct ListColumn {
  std::vector<T> values;
  std::vector<std::size_t> row_lengths;
};

class ParquetReader {
 public:
  // Opens the file and parses its footer and schema.
  explicit ParquetReader(std::string path);
  ~ParquetReader();
  ParquetReader(const ParquetReader&) = delete;
  ParquetReader& operator=(const ParquetReader&) = delete;

  const std::string& path() const { return path_; }
  std::int64_t num_rows() const;
  std::size_t num_row_groups() const;
  // The primitive columns in file order; path[0] is the name a column is read by.
  const std::vector<LeafColumn>& columns() const { return leaves_; }
  std::vector<std::string> column_names() const;
  const std::vector<std::pair<std::string, std::string>>& key_value_metadata() const;
  const std::string& created_by() const;

  // T is bool, std::int32_t, std::int64_t, float, double or std::string and must match the
  // column's physical type (BOOLEAN, INT32, INT64, FLOAT, DOUBLE, BYTE_ARRAY).
  // A scalar column, one value per row; throws on a null.
  template <typename T>
  std::vector<T> ReadColumn(const std::string& name) const;
  // A list column (or a scalar one, as lists of 0 or 1 items).
  template <typename T>
  ListColumn<T> ReadListColumn(const std::string& name) const;

 private:
  std::size_t LeafIndex(const std::string& name) const;
  std::vector<std::uint8_t> ReadRange(std::int64_t offset, std::int64_t size, const std::string& what) const;

  std::string path_;
  int fd_ = -1;
  std::uint64_t file_size_ = 0;
  std::uint64_t data_end_ = 0;  // where the footer starts: no page reaches past it
  std::unique_ptr<FileMetadata> metadata_;
  std::vector<LeafColumn> leaves_;
};

}  // namespace tavis::batch::dataset::parquet
