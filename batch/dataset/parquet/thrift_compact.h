// The Thrift compact protocol, the serialization of Parquet's footer and page headers: an encoder
// that appends fields to a byte vector, and a bounded decoder that walks structs field by field.
// Only what Parquet uses: i16/i32/i64 (zigzag varints), bool, binary/string, list and struct.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace tavis::batch::dataset::parquet {

// The type nibbles of the compact protocol.
enum class ThriftType : std::uint8_t {
  kStop = 0,
  kBoolTrue = 1,
  kBoolFalse = 2,
  kByte = 3,
  kI16 = 4,
  kI32 = 5,
  kI64 = 6,
  kDouble = 7,
  kBinary = 8,
  kList = 9,
  kSet = 10,
  kMap = 11,
  kStruct = 12,
};

void AppendUleb128(std::uint64_t value, std::vector<std::uint8_t>& out);
std::uint64_t ZigZag(std::int64_t value);
std::int64_t UnZigZag(std::uint64_t value);

// Reads a ULEB128 varint at `position` of [data, data + size), advancing `position`. Returns
// false, leaving `value` undefined, when it runs past the end or beyond 10 bytes.
bool ReadUleb128(const std::uint8_t* data, std::size_t size, std::size_t& position, std::uint64_t& value);

// Appends fields to `out`. Field ids of one struct must increase; nested structs are opened with
// BeginStruct* and closed with EndStruct, which writes the stop byte.
class ThriftCompactWriter {
 public:
  explicit ThriftCompactWriter(std::vector<std::uint8_t>& out) : out_(out) {}

  void I16Field(std::int16_t id, std::int16_t value);
  void I32Field(std::int16_t id, std::int32_t value);
  void I64Field(std::int16_t id, std::int64_t value);
  void BoolField(std::int16_t id, bool value);
  void BinaryField(std::int16_t id, std::string_view value);
  // A struct-valued field; its fields follow, then EndStruct.
  void BeginStructField(std::int16_t id);
  // A list-valued field of `size` elements of `element_type`; the elements follow (I32, Binary,
  // or BeginStruct ... EndStruct each).
  void ListField(std::int16_t id, ThriftType element_type, std::size_t size);

  // List elements.
  void I32(std::int32_t value);
  void Binary(std::string_view value);
  void BeginStruct();

  // Ends the innermost open struct (the top-level struct too).
  void EndStruct();

 private:
  void FieldHeader(std::int16_t id, ThriftType type);

  std::vector<std::uint8_t>& out_;
  std::vector<std::int16_t> last_field_ids_{0};  // one per open struct; the top level is open
};

// Decodes from a byte range it never reads past. Every error throws std::runtime_error that
// starts with `context` (e.g. "file.parquet: footer") and says what is wrong.
class ThriftCompactReader {
 public:
  ThriftCompactReader(const std::uint8_t* data, std::size_t size, std::string context);

  // Reads one struct: calls `on_field(id, type)` for every field, which must consume the value
  // (with the readers below, ReadStruct for a nested struct, or Skip). Consumes the stop byte.
  void ReadStruct(const std::function<void(std::int16_t id, ThriftType type)>& on_field);
  // The same for a struct-valued field of `type`, which must be a struct.
  void ReadStruct(ThriftType type, const std::function<void(std::int16_t id, ThriftType type)>& on_field);

  std::int64_t ReadInt(ThriftType type);  // i16, i32 or i64, checked against `type`
  std::int32_t ReadI32(ThriftType type);  // an i32 field or enum; rejects values out of range
  bool ReadBool(ThriftType type);         // a bool field carries its value in its type nibble
  std::string ReadBinary(ThriftType type);
  // The element type and size of a list; the size is bounded by the bytes left.
  std::size_t ReadListHeader(ThriftType type, ThriftType& element_type);
  void Skip(ThriftType type);

  std::size_t position() const { return position_; }
  [[noreturn]] void Fail(const std::string& what) const;

 private:
  std::uint8_t ReadByte();
  std::uint64_t ReadUleb128();
  void Expect(ThriftType actual, ThriftType expected) const;
  void SkipValue(ThriftType type, int depth);

  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t position_ = 0;
  std::string context_;
  int struct_depth_ = 0;
};

}  // namespace tavis::batch::dataset::parquet
