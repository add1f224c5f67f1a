// A streaming Parquet writer for LeRobot datasets: one row group per WriteRowGroup call (one per
// episode), the footer at Close. Columns are OPTIONAL scalars or 3-level LISTs (see
// parquet_schema.h), with no nulls; each column chunk is one data page v1 with PLAIN values and
// RLE levels, UNCOMPRESSED or SNAPPY (the default, as LeRobot writes). No timestamps: the same
// input gives byte-identical files.
//
// The file is written to `path + ".partial"` and renamed to `path` by Close, so an interrupted run
// never leaves a truncated file under the real name; a writer destroyed without Close removes it.
//
//   ParquetWriter writer(path, {ColumnSpec::List("action", ValueType::kFloat, {19}),
//                               ColumnSpec::Scalar("frame_index", ValueType::kInt64)});
//   RowGroupBuilder rows = writer.NewRowGroup(frames);
//   rows.AddList("action", actions);        // frames * 19 floats, row after row
//   rows.Add("frame_index", frame_indices);  // frames int64
//   writer.WriteRowGroup(rows);
//   rows.Reset(next_frames);                 // reuses the buffers for the next episode
//   ...
//   writer.Close();
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "batch/dataset/parquet/parquet_format.h"
#include "batch/dataset/parquet/parquet_schema.h"

namespace tavis::batch::dataset::parquet {

struct ParquetWriterOptions {
  Codec codec = Codec::kSnappy;  // kUncompressed or kSnappy
  // FileMetaData key_value_metadata, in this order (tasks.parquet needs "pandas").
  std::vector<std::pair<std::string, std::string>> key_value_metadata;
  std::string created_by = "tavis-cpp parquet writer version 1.0";
};

struct WriterSchema;  // the columns and codec a writer and its row groups share

// The encoded column chunks of one row group, filled by column name, in any order, each column
// once. Value types: bool, std::int32_t, std::int64_t, float, double, std::string; they must match
// the column's ValueType. Every Add* throws std::invalid_argument naming the column for an
// unknown or already filled column, a type mismatch, or a count that does not match the rows.
// Made by ParquetWriter::NewRowGroup; it keeps the writer's schema alive on its own.
class RowGroupBuilder {
 public:
  // A scalar column: one value per row.
  template <typename T>
  void Add(const std::string& column, const std::vector<T>& values);

  // A list column: the items of all rows, row after row. `row_lengths` (one per row) is required
  // for a column declared without a shape (a length of 0 writes an empty list, not a null);
  // otherwise leave it empty and each row takes the product of the shape's axes, row-major.
  template <typename T>
  void AddList(const std::string& column, const std::vector<T>& values,
               const std::vector<std::size_t>& row_lengths = {});

  // Forgets the columns, keeping the buffers, for another row group of `num_rows` rows.
  void Reset(std::size_t num_rows);

  std::size_t num_rows() const { return num_rows_; }

 private:
  friend class ParquetWriter;

  RowGroupBuilder(std::shared_ptr<const WriterSchema> schema, std::size_t num_rows);

  struct EncodedChunk {
    bool filled = false;
    std::vector<std::uint8_t> page;      // PageHeader then the (compressed) body
    std::int64_t num_values = 0;         // level entries
    std::int64_t uncompressed_size = 0;  // PageHeader plus uncompressed body
  };

  template <typename T>
  void Encode(const std::string& column, const std::vector<T>& values, bool as_list,
              const std::vector<std::size_t>& row_lengths);
  const ColumnSpec& Claim(const std::string& column, ValueType type, bool as_list);

  std::shared_ptr<const WriterSchema> schema_;
  std::size_t num_rows_;
  std::vector<EncodedChunk> chunks_;  // in schema order
  // Scratch buffers reused across columns.
  std::vector<std::uint8_t> repetition_levels_;
  std::vector<std::uint8_t> definition_levels_;
  std::vector<std::uint8_t> body_;
  std::vector<std::uint8_t> compressed_;
};

class ParquetWriter {
 public:
  // Validates the schema (std::invalid_argument naming the column, see ValidateColumns), opens
  // `path + ".partial"` and writes the leading magic. Throws std::runtime_error naming the path
  // and the system's reason when the file cannot be created or written.
  ParquetWriter(std::string path, std::vector<ColumnSpec> columns, ParquetWriterOptions options = {});
  ~ParquetWriter();  // without Close: closes and removes the partial file
  ParquetWriter(const ParquetWriter&) = delete;
  ParquetWriter& operator=(const ParquetWriter&) = delete;

  // An empty row group of `num_rows` (at least 1) rows for this writer's columns.
  RowGroupBuilder NewRowGroup(std::size_t num_rows) const;

  // Appends the row group. Throws std::invalid_argument naming the first column not filled (or a
  // builder from another writer), std::runtime_error naming the path on a failed write (after
  // which the writer is unusable and the partial file is removed on destruction).
  void WriteRowGroup(const RowGroupBuilder& rows);

  // Writes the footer, closes the file (checking the result) and renames it to `path`.
  void Close();

  // Bytes in the file so far (the footer counts once Close has written it).
  std::uint64_t bytes_written() const { return bytes_written_; }
  std::int64_t num_rows() const { return num_rows_; }
  const std::string& path() const { return path_; }

 private:
  struct ChunkLocation {
    std::int64_t offset;
    std::int64_t num_values;
    std::int64_t uncompressed_size;
    std::int64_t compressed_size;
  };
  struct RowGroupLocation {
    std::int64_t num_rows;
    std::vector<ChunkLocation> chunks;
  };

  void WriteBytes(const std::uint8_t* data, std::size_t size);
  void CheckUsable(const char* operation) const;
  std::vector<std::uint8_t> EncodeFooter() const;

  std::string path_;
  std::string partial_path_;
  std::shared_ptr<const WriterSchema> schema_;
  ParquetWriterOptions options_;
  int fd_ = -1;
  bool failed_ = false;
  bool closed_ = false;
  std::uint64_t bytes_written_ = 0;
  std::int64_t num_rows_ = 0;
  std::vector<RowGroupLocation> row_groups_;
};

}  // namespace tavis::batch::dataset::parquet
