#include "batch/dataset/parquet/parquet_writer.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

#include "batch/dataset/parquet/page_compression.h"
#include "batch/dataset/parquet/rle_levels.h"
#include "batch/dataset/parquet/thrift_compact.h"

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "PLAIN values are copied as little-endian bytes");

namespace tavis::batch::dataset::parquet {

struct WriterSchema {
  std::vector<ColumnSpec> columns;
  std::unordered_map<std::string, std::size_t> index_of_name;
  Codec codec = Codec::kSnappy;
};

namespace {

constexpr std::uint8_t kMagic[] = {'P', 'A', 'R', '1'};

std::invalid_argument ColumnError(const std::string& column, const std::string& what) {
  return std::invalid_argument("Parquet column \"" + column + "\": " + what);
}

template <typename T>
void AppendPlain(const std::vector<T>& values, const std::string&, std::vector<std::uint8_t>& out) {
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(values.data());
  out.insert(out.end(), bytes, bytes + values.size() * sizeof(T));
}

void AppendPlain(const std::vector<bool>& values, const std::string&, std::vector<std::uint8_t>& out) {
  const std::size_t start = out.size();
  out.resize(start + (values.size() + 7) / 8, 0);
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (values[i]) out[start + i / 8] = static_cast<std::uint8_t>(out[start + i / 8] | (1U << (i % 8)));
  }
}

void AppendPlain(const std::vector<std::string>& values, const std::string& column, std::vector<std::uint8_t>& out) {
  for (const std::string& value : values) {
    if (value.size() > std::numeric_limits<std::uint32_t>::max()) throw ColumnError(column, "string longer than 4 GiB");
    const auto length = static_cast<std::uint32_t>(value.size());
    for (int byte = 0; byte < 4; ++byte) out.push_back(static_cast<std::uint8_t>(length >> (8 * byte)));
    out.insert(out.end(), value.begin(), value.end());
  }
}

// Levels of `num_rows` rows of `items_per_row` leaves in a list nested as deep as `shape`: a
// leaf's repetition level is 0 for the first of a row, else 1 + the outermost axis whose index
// changed, which is the outermost axis whose stride divides the leaf's position.
void FixedShapeRepetition(const std::vector<std::size_t>& shape, std::size_t num_rows,
                          std::vector<std::uint8_t>& levels) {
  std::vector<std::size_t> strides(shape.size(), 1);
  for (std::size_t axis = shape.size() - 1; axis > 0; --axis) strides[axis - 1] = strides[axis] * shape[axis];
  const std::size_t items = strides[0] * shape[0];
  levels.clear();
  for (std::size_t row = 0; row < num_rows; ++row) {
    levels.push_back(0);
    for (std::size_t leaf = 1; leaf < items; ++leaf) {
      std::size_t axis = 0;
      while (leaf % strides[axis] != 0) ++axis;
      levels.push_back(static_cast<std::uint8_t>(axis + 1));
    }
  }
}

std::int32_t PageSize(std::size_t size, const std::string& column) {
  if (size > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    throw ColumnError(column, "page of " + std::to_string(size) + " bytes exceeds the 2 GiB Parquet limit");
  }
  return static_cast<std::int32_t>(size);
}

std::string SystemError(const std::string& what, const std::string& path) {
  return what + " " + path + ": " + std::strerror(errno);
}

}  // namespace

RowGroupBuilder::RowGroupBuilder(std::shared_ptr<const WriterSchema> schema, std::size_t num_rows)
    : schema_(std::move(schema)), num_rows_(num_rows), chunks_(schema_->columns.size()) {
  if (num_rows == 0) throw std::invalid_argument("a Parquet row group needs at least one row");
}

void RowGroupBuilder::Reset(std::size_t num_rows) {
  if (num_rows == 0) throw std::invalid_argument("a Parquet row group needs at least one row");
  num_rows_ = num_rows;
  for (EncodedChunk& chunk : chunks_) chunk.filled = false;
}

const ColumnSpec& RowGroupBuilder::Claim(const std::string& column, ValueType type, bool as_list) {
  const auto found = schema_->index_of_name.find(column);
  if (found == schema_->index_of_name.end()) throw ColumnError(column, "not in the schema");
  const ColumnSpec& spec = schema_->columns[found->second];
  if (spec.type != type) {
    throw ColumnError(column, "declared " + ValueTypeName(spec.type) + ", given " + ValueTypeName(type) + " values");
  }
  if (spec.is_list != as_list) throw ColumnError(column, spec.is_list ? "is a list column" : "is a scalar column");
  if (chunks_[found->second].filled) throw ColumnError(column, "filled twice in one row group");
  return spec;
}

template <typename T>
void RowGroupBuilder::Add(const std::string& column, const std::vector<T>& values) {
  Encode(column, values, false, {});
}

template <typename T>
void RowGroupBuilder::AddList(const std::string& column, const std::vector<T>& values,
                              const std::vector<std::size_t>& row_lengths) {
  Encode(column, values, true, row_lengths);
}

template <typename T>
void RowGroupBuilder::Encode(const std::string& column, const std::vector<T>& values, bool as_list,
                             const std::vector<std::size_t>& row_lengths) {
  const ColumnSpec& spec = Claim(column, ValueTypeOf<T>::kType, as_list);
  const auto max_definition = static_cast<std::uint8_t>(spec.max_definition_level());
  repetition_levels_.clear();
  definition_levels_.clear();
  if (!spec.is_list || !spec.shape.empty()) {
    if (!row_lengths.empty()) throw ColumnError(column, "has a fixed shape; row lengths are not taken");
    const std::size_t expected = num_rows_ * spec.items_per_row();
    if (values.size() != expected) {
      throw ColumnError(column, std::to_string(values.size()) + " values for " + std::to_string(num_rows_) +
                                    " rows of " + std::to_string(spec.items_per_row()) + " (expected " +
                                    std::to_string(expected) + ")");
    }
    if (spec.is_list) FixedShapeRepetition(spec.shape, num_rows_, repetition_levels_);
    definition_levels_.assign(values.size(), max_definition);
  } else {
    if (row_lengths.size() != num_rows_) {
      throw ColumnError(column, std::to_string(row_lengths.size()) + " row lengths for " + std::to_string(num_rows_) +
                                    " rows (a list without a shape needs one length per row)");
    }
    const std::size_t total = std::accumulate(row_lengths.begin(), row_lengths.end(), std::size_t{0});
    if (values.size() != total) {
      throw ColumnError(
          column, std::to_string(values.size()) + " values where the row lengths add up to " + std::to_string(total));
    }
    for (const std::size_t length : row_lengths) {
      // An empty list is one entry: repetition 0, defined down to the (present) list group.
      repetition_levels_.push_back(0);
      definition_levels_.push_back(length == 0 ? static_cast<std::uint8_t>(max_definition - 2) : max_definition);
      for (std::size_t item = 1; item < length; ++item) {
        repetition_levels_.push_back(1);
        definition_levels_.push_back(max_definition);
      }
    }
  }

  body_.clear();
  if (spec.is_list) {
    AppendLevelBlock(repetition_levels_, LevelBitWidth(static_cast<std::uint32_t>(spec.max_repetition_level())), body_);
  }
  AppendLevelBlock(definition_levels_, LevelBitWidth(max_definition), body_);
  AppendPlain(values, column, body_);
  compressed_.clear();
  AppendCompressed(schema_->codec, body_, compressed_);

  EncodedChunk& chunk = chunks_[schema_->index_of_name.at(column)];
  chunk.page.clear();
  ThriftCompactWriter header(chunk.page);
  header.I32Field(1, static_cast<std::int32_t>(PageType::kDataPage));
  header.I32Field(2, PageSize(body_.size(), column));
  header.I32Field(3, PageSize(compressed_.size(), column));
  header.BeginStructField(5);
  header.I32Field(1, PageSize(definition_levels_.size(), column));
  header.I32Field(2, static_cast<std::int32_t>(Encoding::kPlain));
  header.I32Field(3, static_cast<std::int32_t>(Encoding::kRle));
  header.I32Field(4, static_cast<std::int32_t>(Encoding::kRle));
  header.EndStruct();
  header.EndStruct();
  chunk.uncompressed_size = static_cast<std::int64_t>(chunk.page.size() + body_.size());
  chunk.page.insert(chunk.page.end(), compressed_.begin(), compressed_.end());
  chunk.num_values = static_cast<std::int64_t>(definition_levels_.size());
  chunk.filled = true;
}

#define TAVIS_PARQUET_INSTANTIATE(T)                                                \
  template void RowGroupBuilder::Add<T>(const std::string&, const std::vector<T>&); \
  template void RowGroupBuilder::AddList<T>(const std::string&, const std::vector<T>&, const std::vector<std::size_t>&);
TAVIS_PARQUET_FOR_EACH_VALUE_TYPE(TAVIS_PARQUET_INSTANTIATE)
#undef TAVIS_PARQUET_INSTANTIATE

ParquetWriter::ParquetWriter(std::string path, std::vector<ColumnSpec> columns, ParquetWriterOptions options)
    : path_(std::move(path)), partial_path_(path_ + ".partial"), options_(std::move(options)) {
  ValidateColumns(columns);
  if (options_.codec != Codec::kUncompressed && options_.codec != Codec::kSnappy) {
    throw std::invalid_argument("Parquet writer for " + path_ + ": unsupported codec " + CodecName(options_.codec));
  }
  auto schema = std::make_shared<WriterSchema>();
  for (std::size_t i = 0; i < columns.size(); ++i) schema->index_of_name.emplace(columns[i].name, i);
  schema->columns = std::move(columns);
  schema->codec = options_.codec;
  schema_ = std::move(schema);

  fd_ = ::open(partial_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error(SystemError("cannot create Parquet file", partial_path_));
  try {
    WriteBytes(kMagic, sizeof kMagic);
  } catch (...) {
    ::close(fd_);
    ::unlink(partial_path_.c_str());
    throw;
  }
}

ParquetWriter::~ParquetWriter() {
  if (closed_) return;
  if (fd_ >= 0) ::close(fd_);
  ::unlink(partial_path_.c_str());
}

RowGroupBuilder ParquetWriter::NewRowGroup(std::size_t num_rows) const { return RowGroupBuilder(schema_, num_rows); }

void ParquetWriter::CheckUsable(const char* operation) const {
  if (closed_) throw std::logic_error(std::string(operation) + " on the closed Parquet writer of " + path_);
  if (failed_) throw std::runtime_error(std::string(operation) + " after a failed write to " + partial_path_);
}

void ParquetWriter::WriteBytes(const std::uint8_t* data, std::size_t size) {
  while (size > 0) {
    const ssize_t written = ::write(fd_, data, size);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) {
      failed_ = true;
      if (written == 0) errno = EIO;
      throw std::runtime_error(SystemError("cannot write Parquet file", partial_path_));
    }
    data += written;
    size -= static_cast<std::size_t>(written);
    bytes_written_ += static_cast<std::uint64_t>(written);
  }
}

void ParquetWriter::WriteRowGroup(const RowGroupBuilder& rows) {
  CheckUsable("WriteRowGroup");
  if (rows.schema_ != schema_) throw std::invalid_argument("row group from another Parquet writer given to " + path_);
  for (std::size_t i = 0; i < rows.chunks_.size(); ++i) {
    if (!rows.chunks_[i].filled)
      throw ColumnError(schema_->columns[i].name, "not filled in the row group for " + path_);
  }
  RowGroupLocation group{static_cast<std::int64_t>(rows.num_rows_), {}};
  group.chunks.reserve(rows.chunks_.size());
  for (const RowGroupBuilder::EncodedChunk& chunk : rows.chunks_) {
    group.chunks.push_back(ChunkLocation{static_cast<std::int64_t>(bytes_written_), chunk.num_values,
                                         chunk.uncompressed_size, static_cast<std::int64_t>(chunk.page.size())});
    WriteBytes(chunk.page.data(), chunk.page.size());
  }
  num_rows_ += group.num_rows;
  row_groups_.push_back(std::move(group));
}

std::vector<std::uint8_t> ParquetWriter::EncodeFooter() const {
  std::vector<std::uint8_t> footer;
  ThriftCompactWriter thrift(footer);
  thrift.I32Field(1, 1);  // format version 1: nothing here needs 2.x features
  AppendSchemaField(schema_->columns, thrift);
  thrift.I64Field(3, num_rows_);
  thrift.ListField(4, ThriftType::kStruct, row_groups_.size());
  for (const RowGroupLocation& group : row_groups_) {
    std::int64_t uncompressed = 0;
    std::int64_t compressed = 0;
    thrift.BeginStruct();
    thrift.ListField(1, ThriftType::kStruct, group.chunks.size());
    for (std::size_t i = 0; i < group.chunks.size(); ++i) {
      const ChunkLocation& chunk = group.chunks[i];
      const ColumnSpec& column = schema_->columns[i];
      uncompressed += chunk.uncompressed_size;
      compressed += chunk.compressed_size;
      thrift.BeginStruct();
      thrift.I64Field(2, chunk.offset);
      thrift.BeginStructField(3);
      thrift.I32Field(1, static_cast<std::int32_t>(PhysicalTypeOf(column.type)));
      thrift.ListField(2, ThriftType::kI32, 2);
      thrift.I32(static_cast<std::int32_t>(Encoding::kPlain));
      thrift.I32(static_cast<std::int32_t>(Encoding::kRle));
      const std::vector<std::string> path = column.leaf_path();
      thrift.ListField(3, ThriftType::kBinary, path.size());
      for (const std::string& part : path) thrift.Binary(part);
      thrift.I32Field(4, static_cast<std::int32_t>(options_.codec));
      thrift.I64Field(5, chunk.num_values);
      thrift.I64Field(6, chunk.uncompressed_size);
      thrift.I64Field(7, chunk.compressed_size);
      thrift.I64Field(9, chunk.offset);
      thrift.EndStruct();
      thrift.EndStruct();
    }
    thrift.I64Field(2, uncompressed);
    thrift.I64Field(3, group.num_rows);
    thrift.I64Field(5, group.chunks.front().offset);
    thrift.I64Field(6, compressed);
    thrift.EndStruct();
  }
  if (!options_.key_value_metadata.empty()) {
    thrift.ListField(5, ThriftType::kStruct, options_.key_value_metadata.size());
    for (const auto& [key, value] : options_.key_value_metadata) {
      thrift.BeginStruct();
      thrift.BinaryField(1, key);
      thrift.BinaryField(2, value);
      thrift.EndStruct();
    }
  }
  thrift.BinaryField(6, options_.created_by);
  thrift.EndStruct();
  return footer;
}

void ParquetWriter::Close() {
  CheckUsable("Close");
  std::vector<std::uint8_t> tail = EncodeFooter();
  const std::size_t footer_length = tail.size();
  for (int byte = 0; byte < 4; ++byte) tail.push_back(static_cast<std::uint8_t>(footer_length >> (8 * byte)));
  tail.insert(tail.end(), std::begin(kMagic), std::end(kMagic));
  WriteBytes(tail.data(), tail.size());
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) {
    failed_ = true;
    throw std::runtime_error(SystemError("cannot close Parquet file", partial_path_));
  }
  if (::rename(partial_path_.c_str(), path_.c_str()) != 0) {
    failed_ = true;
    throw std::runtime_error(SystemError("cannot rename " + partial_path_ + " to", path_));
  }
  closed_ = true;
}

}  // namespace tavis::batch::dataset::parquet
