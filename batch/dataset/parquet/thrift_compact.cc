#include "batch/dataset/parquet/thrift_compact.h"

#include <limits>
#include <stdexcept>

namespace tavis::batch::dataset::parquet {
namespace {

// Deeper nesting than Parquet's metadata ever uses means a corrupt or hostile footer.
constexpr int kMaxStructDepth = 64;

std::uint8_t Nibble(ThriftType type) { return static_cast<std::uint8_t>(type); }

bool IsInteger(ThriftType type) {
  return type == ThriftType::kI16 || type == ThriftType::kI32 || type == ThriftType::kI64;
}

}  // namespace

void AppendUleb128(std::uint64_t value, std::vector<std::uint8_t>& out) {
  while (value >= 0x80) {
    out.push_back(static_cast<std::uint8_t>(value | 0x80));
    value >>= 7;
  }
  out.push_back(static_cast<std::uint8_t>(value));
}

std::uint64_t ZigZag(std::int64_t value) {
  return (static_cast<std::uint64_t>(value) << 1) ^ static_cast<std::uint64_t>(value >> 63);
}

std::int64_t UnZigZag(std::uint64_t value) {
  return static_cast<std::int64_t>(value >> 1) ^ -static_cast<std::int64_t>(value & 1);
}

bool ReadUleb128(const std::uint8_t* data, std::size_t size, std::size_t& position, std::uint64_t& value) {
  value = 0;
  for (int shift = 0; shift < 64 && position < size; shift += 7) {
    const std::uint8_t byte = data[position++];
    value |= static_cast<std::uint64_t>(byte & 0x7f) << shift;
    if ((byte & 0x80) == 0) return true;
  }
  return false;
}

void ThriftCompactWriter::FieldHeader(std::int16_t id, ThriftType type) {
  std::int16_t& last = last_field_ids_.back();
  const int delta = id - last;
  if (delta > 0 && delta <= 15) {
    out_.push_back(static_cast<std::uint8_t>((delta << 4) | Nibble(type)));
  } else {
    out_.push_back(Nibble(type));
    AppendUleb128(ZigZag(id), out_);
  }
  last = id;
}

void ThriftCompactWriter::I16Field(std::int16_t id, std::int16_t value) {
  FieldHeader(id, ThriftType::kI16);
  AppendUleb128(ZigZag(value), out_);
}

void ThriftCompactWriter::I32Field(std::int16_t id, std::int32_t value) {
  FieldHeader(id, ThriftType::kI32);
  I32(value);
}

void ThriftCompactWriter::I64Field(std::int16_t id, std::int64_t value) {
  FieldHeader(id, ThriftType::kI64);
  AppendUleb128(ZigZag(value), out_);
}

void ThriftCompactWriter::BoolField(std::int16_t id, bool value) {
  FieldHeader(id, value ? ThriftType::kBoolTrue : ThriftType::kBoolFalse);
}

void ThriftCompactWriter::BinaryField(std::int16_t id, std::string_view value) {
  FieldHeader(id, ThriftType::kBinary);
  Binary(value);
}

void ThriftCompactWriter::BeginStructField(std::int16_t id) {
  FieldHeader(id, ThriftType::kStruct);
  BeginStruct();
}

void ThriftCompactWriter::ListField(std::int16_t id, ThriftType element_type, std::size_t size) {
  FieldHeader(id, ThriftType::kList);
  if (size < 15) {
    out_.push_back(static_cast<std::uint8_t>((size << 4) | Nibble(element_type)));
  } else {
    out_.push_back(static_cast<std::uint8_t>(0xF0 | Nibble(element_type)));
    AppendUleb128(size, out_);
  }
}

void ThriftCompactWriter::I32(std::int32_t value) { AppendUleb128(ZigZag(value), out_); }

void ThriftCompactWriter::Binary(std::string_view value) {
  AppendUleb128(value.size(), out_);
  out_.insert(out_.end(), value.begin(), value.end());
}

void ThriftCompactWriter::BeginStruct() { last_field_ids_.push_back(0); }

void ThriftCompactWriter::EndStruct() {
  out_.push_back(Nibble(ThriftType::kStop));
  if (last_field_ids_.size() > 1) last_field_ids_.pop_back();
}

ThriftCompactReader::ThriftCompactReader(const std::uint8_t* data, std::size_t size, std::string context)
    : data_(data), size_(size), context_(std::move(context)) {}

void ThriftCompactReader::Fail(const std::string& what) const {
  throw std::runtime_error(context_ + ": " + what + " (at byte " + std::to_string(position_) + " of " +
                           std::to_string(size_) + ")");
}

std::uint8_t ThriftCompactReader::ReadByte() {
  if (position_ >= size_) Fail("thrift data ends early");
  return data_[position_++];
}

std::uint64_t ThriftCompactReader::ReadUleb128() {
  std::uint64_t value = 0;
  if (!tavis::batch::dataset::parquet::ReadUleb128(data_, size_, position_, value))
    Fail("varint past the end or longer than 10 bytes");
  return value;
}

void ThriftCompactReader::Expect(ThriftType actual, ThriftType expected) const {
  if (actual != expected) {
    Fail("thrift field of type " + std::to_string(Nibble(actual)) + " where type " + std::to_string(Nibble(expected)) +
         " was expected");
  }
}

void ThriftCompactReader::ReadStruct(const std::function<void(std::int16_t, ThriftType)>& on_field) {
  if (++struct_depth_ > kMaxStructDepth) Fail("thrift structs nested deeper than " + std::to_string(kMaxStructDepth));
  std::int16_t last_id = 0;
  for (;;) {
    const std::uint8_t header = ReadByte();
    const auto type = static_cast<ThriftType>(header & 0x0f);
    if (type == ThriftType::kStop) break;
    if (Nibble(type) > Nibble(ThriftType::kStruct)) Fail("unknown thrift type " + std::to_string(Nibble(type)));
    const int delta = header >> 4;
    std::int64_t id = last_id + delta;
    if (delta == 0) {
      id = UnZigZag(ReadUleb128());
    }
    if (id < std::numeric_limits<std::int16_t>::min() || id > std::numeric_limits<std::int16_t>::max()) {
      Fail("thrift field id " + std::to_string(id) + " out of range");
    }
    last_id = static_cast<std::int16_t>(id);
    on_field(last_id, type);
  }
  --struct_depth_;
}

void ThriftCompactReader::ReadStruct(ThriftType type, const std::function<void(std::int16_t, ThriftType)>& on_field) {
  Expect(type, ThriftType::kStruct);
  ReadStruct(on_field);
}

std::int64_t ThriftCompactReader::ReadInt(ThriftType type) {
  if (!IsInteger(type)) Expect(type, ThriftType::kI64);
  return UnZigZag(ReadUleb128());
}

std::int32_t ThriftCompactReader::ReadI32(ThriftType type) {
  const std::int64_t value = ReadInt(type);
  if (value < std::numeric_limits<std::int32_t>::min() || value > std::numeric_limits<std::int32_t>::max()) {
    Fail("i32 value " + std::to_string(value) + " out of range");
  }
  return static_cast<std::int32_t>(value);
}

bool ThriftCompactReader::ReadBool(ThriftType type) {
  if (type != ThriftType::kBoolTrue) Expect(type, ThriftType::kBoolFalse);
  return type == ThriftType::kBoolTrue;
}

std::string ThriftCompactReader::ReadBinary(ThriftType type) {
  Expect(type, ThriftType::kBinary);
  const std::uint64_t length = ReadUleb128();
  if (length > size_ - position_) Fail("string of " + std::to_string(length) + " bytes runs past the end");
  std::string value(reinterpret_cast<const char*>(data_ + position_), static_cast<std::size_t>(length));
  position_ += static_cast<std::size_t>(length);
  return value;
}

std::size_t ThriftCompactReader::ReadListHeader(ThriftType type, ThriftType& element_type) {
  if (type != ThriftType::kSet) Expect(type, ThriftType::kList);
  const std::uint8_t header = ReadByte();
  element_type = static_cast<ThriftType>(header & 0x0f);
  std::uint64_t size = header >> 4;
  if (size == 15) size = ReadUleb128();
  // Every element takes at least one byte, so a longer list cannot fit in what is left.
  if (size > size_ - position_) Fail("list of " + std::to_string(size) + " elements runs past the end");
  return static_cast<std::size_t>(size);
}

void ThriftCompactReader::Skip(ThriftType type) { SkipValue(type, 0); }

void ThriftCompactReader::SkipValue(ThriftType type, int depth) {
  if (depth > kMaxStructDepth) Fail("thrift values nested deeper than " + std::to_string(kMaxStructDepth));
  switch (type) {
    case ThriftType::kBoolTrue:
    case ThriftType::kBoolFalse: return;
    case ThriftType::kByte: ReadByte(); return;
    case ThriftType::kI16:
    case ThriftType::kI32:
    case ThriftType::kI64: ReadUleb128(); return;
    case ThriftType::kDouble:
      if (size_ - position_ < 8) Fail("double runs past the end");
      position_ += 8;
      return;
    case ThriftType::kBinary: ReadBinary(type); return;
    case ThriftType::kList:
    case ThriftType::kSet: {
      ThriftType element_type{};
      const std::size_t size = ReadListHeader(type, element_type);
      for (std::size_t i = 0; i < size; ++i) {
        // Bool list elements are one byte each, unlike bool fields.
        if (element_type == ThriftType::kBoolTrue || element_type == ThriftType::kBoolFalse) {
          ReadByte();
        } else {
          SkipValue(element_type, depth + 1);
        }
      }
      return;
    }
    case ThriftType::kMap: {
      const std::uint64_t size = ReadUleb128();
      if (size == 0) return;
      if (size > size_ - position_) Fail("map of " + std::to_string(size) + " entries runs past the end");
      const std::uint8_t types = ReadByte();
      for (std::uint64_t i = 0; i < size; ++i) {
        SkipValue(static_cast<ThriftType>(types >> 4), depth + 1);
        SkipValue(static_cast<ThriftType>(types & 0x0f), depth + 1);
      }
      return;
    }
    case ThriftType::kStruct:
      ReadStruct([&](std::int16_t, ThriftType field_type) { SkipValue(field_type, depth + 1); });
      return;
    case ThriftType::kStop: break;
  }
  Fail("cannot skip thrift type " + std::to_string(Nibble(type)));
}

}  // namespace tavis::batch::dataset::parquet
