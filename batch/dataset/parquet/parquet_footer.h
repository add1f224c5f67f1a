// Decoding of the Thrift structures a Parquet reader needs: the footer's FileMetaData (schema,
// row groups, column chunks, key-value metadata) and the PageHeader before every page. Fields
// this module does not use (statistics, indexes, encryption...) are skipped.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "batch/dataset/parquet/parquet_format.h"
#include "batch/dataset/parquet/parquet_schema.h"
#include "batch/dataset/parquet/thrift_compact.h"

namespace tavis::batch::dataset::parquet {

struct ColumnChunkMetadata {
  PhysicalType type = PhysicalType::kInt64;
  std::vector<std::string> path;
  Codec codec = Codec::kUncompressed;
  std::int64_t num_values = 0;
  std::int64_t total_compressed_size = 0;
  std::int64_t data_page_offset = 0;
  std::optional<std::int64_t> dictionary_page_offset;
  bool in_other_file = false;  // ColumnChunk.file_path set: data outside this file
};

struct RowGroupMetadata {
  std::int64_t num_rows = 0;
  std::vector<ColumnChunkMetadata> columns;
};

struct FileMetadata {
  std::vector<SchemaElement> schema;
  std::int64_t num_rows = 0;
  std::vector<RowGroupMetadata> row_groups;
  std::vector<std::pair<std::string, std::string>> key_value_metadata;
  std::string created_by;
};

FileMetadata ReadFileMetadata(ThriftCompactReader& thrift);

struct PageHeader {
  PageType type = PageType::kDataPage;
  std::int32_t uncompressed_page_size = 0;
  std::int32_t compressed_page_size = 0;
  // Data pages (v1 and v2) and dictionary pages.
  std::int32_t num_values = 0;
  Encoding encoding = Encoding::kPlain;
  // v1 only.
  Encoding definition_level_encoding = Encoding::kRle;
  Encoding repetition_level_encoding = Encoding::kRle;
  // v2 only: level bytes precede the values, uncompressed, without length prefixes.
  std::int32_t definition_levels_byte_length = 0;
  std::int32_t repetition_levels_byte_length = 0;
  bool is_compressed = true;
};

PageHeader ReadPageHeader(ThriftCompactReader& thrift);

}  // namespace tavis::batch::dataset::parquet
