#include "batch/dataset/parquet/parquet_reader.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "batch/dataset/parquet/page_compression.h"
#include "batch/dataset/parquet/parquet_footer.h"
#include "batch/dataset/parquet/rle_levels.h"
#include "batch/dataset/parquet/thrift_compact.h"
#include "batch/dataset/parquet/value_decoding.h"

namespace tavis::batch::dataset::parquet {
namespace {

constexpr char kMagic[] = "PAR1";
constexpr std::size_t kMagicSize = 4;
// Level entries a page may hold beyond 8 per byte of its body. Only long runs of nulls compress
// further, and the bound keeps a hostile page from allocating without limit.
constexpr std::size_t kLevelSlack = std::size_t{1} << 20;

// Levels of one page: `count` entries, all `implied` when the column has no such levels.
void DecodeLevels(const std::uint8_t* data, std::size_t size, int max_level, std::size_t count,
                  const std::string& context, std::vector<std::uint32_t>& levels) {
  if (max_level == 0) {
    levels.assign(count, 0);
    return;
  }
  DecodeHybrid(data, size, LevelBitWidth(static_cast<std::uint32_t>(max_level)), count,
               static_cast<std::uint32_t>(max_level), context, levels);
}

// The pages of one column chunk, decoded into rows.
template <typename T>
class ChunkDecoder {
 public:
  ChunkDecoder(const LeafColumn& leaf, Codec codec, std::string context, ListColumn<T>& out)
      : leaf_(leaf), codec_(codec), context_(std::move(context)), out_(out) {}

  void Decode(const std::vector<std::uint8_t>& chunk, std::int64_t num_values) {
    std::size_t position = 0;
    std::int64_t values_seen = 0;
    while (values_seen < num_values) {
      if (position >= chunk.size()) {
        Fail("column chunk ends after " + std::to_string(values_seen) + " of " + std::to_string(num_values) +
             " values");
      }
      ThriftCompactReader thrift(chunk.data() + position, chunk.size() - position,
                                 context_ + ": page header at chunk byte " + std::to_string(position));
      const PageHeader page = ReadPageHeader(thrift);
      position += thrift.position();
      if (page.compressed_page_size < 0 || page.uncompressed_page_size < 0 || page.num_values < 0) {
        Fail("page header with a negative size or count");
      }
      const auto page_size = static_cast<std::size_t>(page.compressed_page_size);
      if (page_size > chunk.size() - position) {
        Fail("page of " + std::to_string(page_size) + " bytes runs past the end of its column chunk");
      }
      const std::uint8_t* body = chunk.data() + position;
      position += page_size;
      if (page.type == PageType::kDictionaryPage) {
        ReadDictionary(page, body);
      } else if (page.type == PageType::kDataPage || page.type == PageType::kDataPageV2) {
        if (page.num_values > num_values - values_seen) Fail("pages hold more values than the column chunk");
        ReadDataPage(page, body);
        values_seen += page.num_values;
      }
    }
  }

 private:
  [[noreturn]] void Fail(const std::string& what) const { throw std::runtime_error(context_ + ": " + what); }

  void ReadDictionary(const PageHeader& page, const std::uint8_t* body) {
    Decompress(codec_, body, static_cast<std::size_t>(page.compressed_page_size),
               static_cast<std::size_t>(page.uncompressed_page_size), context_ + ": dictionary page", buffer_);
    if (page.encoding != Encoding::kPlain && page.encoding != Encoding::kPlainDictionary) {
      Fail("dictionary page encoded " + EncodingName(page.encoding));
    }
    dictionary_.clear();
    DecodeValues(Encoding::kPlain, buffer_.data(), buffer_.size(), static_cast<std::size_t>(page.num_values),
                 context_ + ": dictionary page", dictionary_);
  }

  void ReadDataPage(const PageHeader& page, const std::uint8_t* body) {
    const auto count = static_cast<std::size_t>(page.num_values);
    const auto compressed_size = static_cast<std::size_t>(page.compressed_page_size);
    const auto uncompressed_size = static_cast<std::size_t>(page.uncompressed_page_size);
    if (count > 8 * uncompressed_size + kLevelSlack) {
      Fail("page of " + std::to_string(uncompressed_size) + " bytes claims " + std::to_string(count) + " values");
    }
    const std::uint8_t* values = nullptr;
    std::size_t values_size = 0;
    if (page.type == PageType::kDataPage) {
      Decompress(codec_, body, compressed_size, uncompressed_size, context_ + ": data page", buffer_);
      std::size_t position = 0;
      const auto level_block = [&](int max_level, Encoding encoding, const char* kind,
                                   std::vector<std::uint32_t>& levels) {
        if (max_level == 0) return DecodeLevels(nullptr, 0, 0, count, context_, levels);
        if (encoding != Encoding::kRle)
          Fail(std::string(kind) + " levels encoded " + EncodingName(encoding) + ", unsupported");
        if (buffer_.size() - position < 4) Fail(std::string(kind) + " level length past the end of the page");
        const std::uint32_t length = LoadUint32Le(buffer_.data() + position);
        position += 4;
        if (length > buffer_.size() - position) Fail(std::string(kind) + " levels past the end of the page");
        DecodeLevels(buffer_.data() + position, length, max_level, count, context_ + ": " + kind + " levels", levels);
        position += length;
      };
      level_block(leaf_.max_repetition_level, page.repetition_level_encoding, "repetition", repetition_);
      level_block(leaf_.max_definition_level, page.definition_level_encoding, "definition", definition_);
      values = buffer_.data() + position;
      values_size = buffer_.size() - position;
    } else {
      if (page.repetition_levels_byte_length < 0 || page.definition_levels_byte_length < 0)
        Fail("negative level length");
      const auto repetition_size = static_cast<std::size_t>(page.repetition_levels_byte_length);
      const auto definition_size = static_cast<std::size_t>(page.definition_levels_byte_length);
      const std::size_t levels_size = repetition_size + definition_size;
      if (levels_size > compressed_size || levels_size > uncompressed_size) Fail("levels larger than their page");
      DecodeLevels(body, repetition_size, leaf_.max_repetition_level, count, context_ + ": repetition levels",
                   repetition_);
      DecodeLevels(body + repetition_size, definition_size, leaf_.max_definition_level, count,
                   context_ + ": definition levels", definition_);
      const Codec codec = page.is_compressed ? codec_ : Codec::kUncompressed;
      Decompress(codec, body + levels_size, compressed_size - levels_size, uncompressed_size - levels_size,
                 context_ + ": data page v2", buffer_);
      values = buffer_.data();
      values_size = buffer_.size();
    }
    const auto max_definition = static_cast<std::uint32_t>(leaf_.max_definition_level);
    const auto present = static_cast<std::size_t>(std::count(definition_.begin(), definition_.end(), max_definition));
    ReadValues(page.encoding, values, values_size, present);
    AssembleRows();
  }

  void ReadValues(Encoding encoding, const std::uint8_t* data, std::size_t size, std::size_t present) {
    page_values_.clear();
    if (encoding != Encoding::kPlainDictionary && encoding != Encoding::kRleDictionary) {
      DecodeValues(encoding, data, size, present, context_ + ": values", page_values_);
      return;
    }
    if (present == 0) return;
    if (dictionary_.empty()) Fail("dictionary-encoded page without a dictionary page");
    if (size < 1) Fail("dictionary indices missing");
    DecodeHybrid(data + 1, size - 1, data[0], present, static_cast<std::uint32_t>(dictionary_.size() - 1),
                 context_ + ": dictionary indices", indices_);
    for (const std::uint32_t index : indices_) page_values_.push_back(dictionary_[index]);
  }

  // Levels to rows: a repetition level of 0 starts a row; a definition level at the maximum
  // carries a value, anything lower is a null or an empty list.
  void AssembleRows() {
    const auto max_definition = static_cast<std::uint32_t>(leaf_.max_definition_level);
    std::size_t next_value = 0;
    for (std::size_t i = 0; i < definition_.size(); ++i) {
      if (repetition_[i] == 0) {
        out_.row_lengths.push_back(0);
      } else if (!row_started_) {
        Fail("the column chunk starts in the middle of a row");
      }
      row_started_ = true;
      if (definition_[i] == max_definition) {
        out_.values.push_back(page_values_[next_value++]);
        ++out_.row_lengths.back();
      }
    }
  }

  const LeafColumn& leaf_;
  Codec codec_;
  std::string context_;
  ListColumn<T>& out_;
  bool row_started_ = false;
  std::vector<std::uint8_t> buffer_;
  std::vector<std::uint32_t> repetition_;
  std::vector<std::uint32_t> definition_;
  std::vector<std::uint32_t> indices_;
  std::vector<T> dictionary_;
  std::vector<T> page_values_;
};

std::string SystemError(const std::string& what, const std::string& path) {
  return what + " " + path + ": " + std::strerror(errno);
}

}  // namespace

ParquetReader::ParquetReader(std::string path) : path_(std::move(path)) {
  fd_ = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error(SystemError("cannot open Parquet file", path_));
  struct stat status {};
  if (::fstat(fd_, &status) != 0) {
    const std::string message = SystemError("cannot stat Parquet file", path_);
    ::close(fd_);
    throw std::runtime_error(message);
  }
  try {
    file_size_ = static_cast<std::uint64_t>(status.st_size);
    if (file_size_ < 2 * kMagicSize + 4) {
      throw std::runtime_error(path_ + ": not a Parquet file: " + std::to_string(file_size_) +
                               " bytes, too short for the magic and footer length");
    }
    const std::vector<std::uint8_t> head = ReadRange(0, kMagicSize, "leading magic");
    if (std::memcmp(head.data(), kMagic, kMagicSize) != 0) {
      throw std::runtime_error(path_ + ": bad magic at the start (not a Parquet file)");
    }
    const std::vector<std::uint8_t> tail =
        ReadRange(static_cast<std::int64_t>(file_size_ - kMagicSize - 4), kMagicSize + 4, "footer length and magic");
    if (std::memcmp(tail.data() + 4, "PARE", kMagicSize) == 0) {
      throw std::runtime_error(path_ + ": encrypted footer, unsupported");
    }
    if (std::memcmp(tail.data() + 4, kMagic, kMagicSize) != 0) {
      throw std::runtime_error(path_ + ": bad magic at the end (truncated or not a Parquet file)");
    }
    const std::uint32_t footer_length = LoadUint32Le(tail.data());
    if (footer_length > file_size_ - 2 * kMagicSize - 4) {
      throw std::runtime_error(path_ + ": footer length " + std::to_string(footer_length) + " beyond the file of " +
                               std::to_string(file_size_) + " bytes");
    }
    data_end_ = file_size_ - kMagicSize - 4 - footer_length;
    const std::vector<std::uint8_t> footer = ReadRange(static_cast<std::int64_t>(data_end_), footer_length, "footer");
    ThriftCompactReader thrift(footer.data(), footer.size(), path_ + ": footer");
    metadata_ = std::make_unique<FileMetadata>(ReadFileMetadata(thrift));
    leaves_ = LeafColumnsOf(metadata_->schema, path_);
    for (std::size_t group = 0; group < metadata_->row_groups.size(); ++group) {
      const RowGroupMetadata& row_group = metadata_->row_groups[group];
      if (row_group.columns.size() != leaves_.size()) {
        throw std::runtime_error(path_ + ": row group " + std::to_string(group) + " has " +
                                 std::to_string(row_group.columns.size()) + " column chunks for " +
                                 std::to_string(leaves_.size()) + " schema columns");
      }
      if (row_group.num_rows < 0)
        throw std::runtime_error(path_ + ": row group " + std::to_string(group) + " has negative rows");
    }
  } catch (...) {
    ::close(fd_);
    throw;
  }
}

ParquetReader::~ParquetReader() { ::close(fd_); }

std::int64_t ParquetReader::num_rows() const { return metadata_->num_rows; }
std::size_t ParquetReader::num_row_groups() const { return metadata_->row_groups.size(); }

const std::vector<std::pair<std::string, std::string>>& ParquetReader::key_value_metadata() const {
  return metadata_->key_value_metadata;
}

const std::string& ParquetReader::created_by() const { return metadata_->created_by; }

std::vector<std::string> ParquetReader::column_names() const {
  std::vector<std::string> names;
  for (const LeafColumn& leaf : leaves_) {
    if (names.empty() || names.back() != leaf.path[0]) names.push_back(leaf.path[0]);
  }
  return names;
}

std::vector<std::uint8_t> ParquetReader::ReadRange(std::int64_t offset, std::int64_t size,
                                                   const std::string& what) const {
  if (offset < 0 || size < 0 || static_cast<std::uint64_t>(offset) > file_size_ ||
      static_cast<std::uint64_t>(size) > file_size_ - static_cast<std::uint64_t>(offset)) {
    throw std::runtime_error(path_ + ": " + what + " at offset " + std::to_string(offset) + " of " +
                             std::to_string(size) + " bytes lies past the end of the file (" +
                             std::to_string(file_size_) + " bytes)");
  }
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(size));
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t got =
        ::pread(fd_, bytes.data() + done, bytes.size() - done, static_cast<off_t>(offset) + static_cast<off_t>(done));
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) throw std::runtime_error(SystemError("cannot read " + what + " of", path_));
    if (got == 0) throw std::runtime_error(path_ + ": file shrank while reading its " + what);
    done += static_cast<std::size_t>(got);
  }
  return bytes;
}

std::size_t ParquetReader::LeafIndex(const std::string& name) const {
  std::size_t found = leaves_.size();
  for (std::size_t i = 0; i < leaves_.size(); ++i) {
    if (leaves_[i].path[0] != name) continue;
    if (found != leaves_.size()) {
      throw std::runtime_error(path_ + ": column \"" + name + "\" is a struct of several columns, unsupported");
    }
    found = i;
  }
  if (found == leaves_.size()) throw std::runtime_error(path_ + ": no column \"" + name + "\"");
  return found;
}

template <typename T>
ListColumn<T> ParquetReader::ReadListColumn(const std::string& name) const {
  const std::size_t leaf_index = LeafIndex(name);
  const LeafColumn& leaf = leaves_[leaf_index];
  if (leaf.type != PhysicalTypeOf(ValueTypeOf<T>::kType)) {
    throw std::runtime_error(path_ + ": column \"" + name + "\" holds " + PhysicalTypeName(leaf.type) + ", read as " +
                             PhysicalTypeName(PhysicalTypeOf(ValueTypeOf<T>::kType)));
  }
  ListColumn<T> column;
  for (std::size_t group = 0; group < metadata_->row_groups.size(); ++group) {
    const RowGroupMetadata& row_group = metadata_->row_groups[group];
    const ColumnChunkMetadata& chunk = row_group.columns[leaf_index];
    const std::string context = path_ + ": column \"" + name + "\" in row group " + std::to_string(group);
    if (chunk.codec != Codec::kUncompressed && chunk.codec != Codec::kSnappy && chunk.codec != Codec::kZstd) {
      throw std::runtime_error("unsupported codec " + CodecName(chunk.codec) + " in column \"" + name + "\" of " +
                               path_);
    }
    if (chunk.in_other_file) throw std::runtime_error(context + ": column chunk stored in another file, unsupported");
    if (chunk.type != leaf.type) throw std::runtime_error(context + ": chunk type differs from the schema");
    std::int64_t start = chunk.data_page_offset;
    if (chunk.dictionary_page_offset && *chunk.dictionary_page_offset > 0 && *chunk.dictionary_page_offset < start) {
      start = *chunk.dictionary_page_offset;
    }
    if (start < static_cast<std::int64_t>(kMagicSize) || chunk.total_compressed_size < 0 ||
        static_cast<std::uint64_t>(start) > data_end_ ||
        static_cast<std::uint64_t>(chunk.total_compressed_size) > data_end_ - static_cast<std::uint64_t>(start)) {
      throw std::runtime_error(context + ": column chunk at offset " + std::to_string(start) + " of " +
                               std::to_string(chunk.total_compressed_size) + " bytes lies outside the data (" +
                               std::to_string(data_end_) + " bytes before the footer)");
    }
    if (chunk.num_values < 0) throw std::runtime_error(context + ": negative value count");
    const std::vector<std::uint8_t> bytes = ReadRange(start, chunk.total_compressed_size, "column chunk");
    const std::size_t rows_before = column.row_lengths.size();
    ChunkDecoder<T>(leaf, chunk.codec, context, column).Decode(bytes, chunk.num_values);
    const std::size_t rows = column.row_lengths.size() - rows_before;
    if (rows != static_cast<std::uint64_t>(row_group.num_rows)) {
      throw std::runtime_error(context + ": " + std::to_string(rows) + " rows where the row group has " +
                               std::to_string(row_group.num_rows));
    }
  }
  return column;
}

template <typename T>
std::vector<T> ParquetReader::ReadColumn(const std::string& name) const {
  if (leaves_[LeafIndex(name)].max_repetition_level != 0) {
    throw std::runtime_error(path_ + ": column \"" + name + "\" is a list column; read it with ReadListColumn");
  }
  ListColumn<T> column = ReadListColumn<T>(name);
  for (std::size_t row = 0; row < column.row_lengths.size(); ++row) {
    if (column.row_lengths[row] != 1) {
      throw std::runtime_error(path_ + ": column \"" + name + "\" is null in row " + std::to_string(row));
    }
  }
  return std::move(column.values);
}

#define TAVIS_PARQUET_INSTANTIATE(T)                                              \
  template std::vector<T> ParquetReader::ReadColumn<T>(const std::string&) const; \
  template ListColumn<T> ParquetReader::ReadListColumn<T>(const std::string&) const;
TAVIS_PARQUET_FOR_EACH_VALUE_TYPE(TAVIS_PARQUET_INSTANTIATE)
#undef TAVIS_PARQUET_INSTANTIATE

}  // namespace tavis::batch::dataset::parquet
