#include "batch/remote/msgpack_decoder.h"

#include <cstring>
#include <stdexcept>
#include <string>

#include "batch/remote/remote_error.h"

namespace tavis::batch::remote {
namespace {

class Decoder {
 public:
  Decoder(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  Value DecodeWhole() {
    Value value = DecodeValue(0);
    if (position_ != size_) {
      throw MsgpackError(std::to_string(size_ - position_) + " trailing bytes after the value", position_);
    }
    return value;
  }

 private:
  Value DecodeValue(int depth) {
    if (depth > kMaxMsgpackDepth) {
      throw MsgpackError("nesting deeper than " + std::to_string(kMaxMsgpackDepth), position_);
    }
    const std::size_t start = position_;
    const std::uint8_t marker = ReadBigEndian(1, "type marker");
    if (marker <= 0x7f) return static_cast<std::int64_t>(marker);
    if (marker >= 0xe0) return static_cast<std::int64_t>(static_cast<std::int8_t>(marker));
    if (marker >= 0xa0 && marker <= 0xbf) return ReadString(marker & 0x1f);
    if (marker >= 0x90 && marker <= 0x9f) return ReadArray(marker & 0x0f, depth);
    if (marker >= 0x80 && marker <= 0x8f) return ReadMap(marker & 0x0f, depth, start);
    switch (marker) {
      case 0xc0: return nullptr;
      case 0xc2: return false;
      case 0xc3: return true;
      case 0xc4: return ReadBinary(ReadBigEndian(1, "bin8 length"));
      case 0xc5: return ReadBinary(ReadBigEndian(2, "bin16 length"));
      case 0xc6: return ReadBinary(ReadBigEndian(4, "bin32 length"));
      case 0xca: return ReadFloat<float, std::uint32_t>("float32");
      case 0xcb: return ReadFloat<double, std::uint64_t>("float64");
      case 0xcc: return ReadBigEndian(1, "uint8");
      case 0xcd: return ReadBigEndian(2, "uint16");
      case 0xce: return ReadBigEndian(4, "uint32");
      case 0xcf: return ReadBigEndian(8, "uint64");
      case 0xd0: return static_cast<std::int64_t>(static_cast<std::int8_t>(ReadBigEndian(1, "int8")));
      case 0xd1: return static_cast<std::int64_t>(static_cast<std::int16_t>(ReadBigEndian(2, "int16")));
      case 0xd2: return static_cast<std::int64_t>(static_cast<std::int32_t>(ReadBigEndian(4, "int32")));
      case 0xd3: return static_cast<std::int64_t>(ReadBigEndian(8, "int64"));
      case 0xd9: return ReadString(ReadBigEndian(1, "str8 length"));
      case 0xda: return ReadString(ReadBigEndian(2, "str16 length"));
      case 0xdb: return ReadString(ReadBigEndian(4, "str32 length"));
      case 0xdc: return ReadArray(ReadBigEndian(2, "array16 length"), depth);
      case 0xdd: return ReadArray(ReadBigEndian(4, "array32 length"), depth);
      case 0xde: return ReadMap(ReadBigEndian(2, "map16 length"), depth, start);
      case 0xdf: return ReadMap(ReadBigEndian(4, "map32 length"), depth, start);
      case 0xc1: throw MsgpackError("never-used marker 0xc1", start);
      default: throw MsgpackError("unsupported ext type marker 0x" + Hex(marker), start);
    }
  }

  static std::string Hex(std::uint8_t byte) {
    static constexpr char kDigits[] = "0123456789abcdef";
    return {kDigits[byte >> 4], kDigits[byte & 0xf]};
  }

  void Need(std::size_t bytes, const char* what) const {
    if (bytes > size_ - position_) {
      throw MsgpackError(std::string("truncated ") + what + ": needs " + std::to_string(bytes) + " bytes, " +
                             std::to_string(size_ - position_) + " left",
                         position_);
    }
  }

  std::uint64_t ReadBigEndian(int bytes, const char* what) {
    Need(static_cast<std::size_t>(bytes), what);
    std::uint64_t number = 0;
    for (int i = 0; i < bytes; ++i) number = (number << 8) | data_[position_++];
    return number;
  }

  template <typename Float, typename Bits>
  Float ReadFloat(const char* what) {
    const auto bits = static_cast<Bits>(ReadBigEndian(sizeof(Bits), what));
    Float number;
    std::memcpy(&number, &bits, sizeof number);
    return number;
  }

  std::string ReadString(std::uint64_t size) {
    Need(size, "str payload");
    std::string text(reinterpret_cast<const char*>(data_ + position_), size);
    position_ += size;
    return text;
  }

  Binary ReadBinary(std::uint64_t size) {
    Need(size, "bin payload");
    Binary binary{std::vector<std::uint8_t>(data_ + position_, data_ + position_ + size)};
    position_ += size;
    return binary;
  }

  // Every entry takes at least one byte, so a count beyond the bytes left is truncation; checking
  // it first keeps a forged count from reserving gigabytes.
  Value ReadArray(std::uint64_t count, int depth) {
    Need(count, "array entries");
    Value::Array items;
    items.reserve(count);
    for (std::uint64_t i = 0; i < count; ++i) items.push_back(DecodeValue(depth + 1));
    return items;
  }

  Value ReadMap(std::uint64_t count, int depth, std::size_t start) {
    if (count > (size_ - position_) / 2) Need(2 * count, "map entries");
    Value::Map entries;
    entries.reserve(count);
    for (std::uint64_t i = 0; i < count; ++i) {
      Value key = DecodeValue(depth + 1);
      Value value = DecodeValue(depth + 1);
      entries.push_back({std::move(key), std::move(value)});
    }
    return ApplyNumpyHook(Value(std::move(entries)), start);
  }

  // openpi's unpack_array: tests for the *bin* keys only.
  static const Value* FindBinKey(const Value& map, std::string_view key) {
    for (const MapEntry& entry : map.as<Value::Map>("map")) {
      const Binary* bytes = entry.key.get_if<Binary>();
      if (bytes != nullptr && bytes->bytes.size() == key.size() &&
          std::memcmp(bytes->bytes.data(), key.data(), key.size()) == 0) {
        return &entry.value;
      }
    }
    return nullptr;
  }

  static Value ApplyNumpyHook(Value map, std::size_t start) {
    if (FindBinKey(map, "__ndarray__") != nullptr) return DecodeNdArray(map, start);
    if (FindBinKey(map, "__npgeneric__") != nullptr) {
      const Value* item = FindBinKey(map, "data");
      if (item == nullptr) throw MsgpackError("__npgeneric__ map has no bin key 'data'", start);
      return *item;
    }
    return map;
  }

  static Value DecodeNdArray(const Value& map, std::size_t start) {
    const Value* data = FindBinKey(map, "data");
    const Value* dtype = FindBinKey(map, "dtype");
    const Value* shape = FindBinKey(map, "shape");
    if (data == nullptr || !data->is<Binary>()) throw MsgpackError("__ndarray__ map needs bin 'data'", start);
    if (dtype == nullptr || !dtype->is<std::string>()) throw MsgpackError("__ndarray__ map needs str 'dtype'", start);
    if (shape == nullptr || !shape->is<Value::Array>())
      throw MsgpackError("__ndarray__ map needs array 'shape'", start);
    NdArray array{dtype->as<std::string>("dtype"), {}, data->as<Binary>("data").bytes};
    for (const Value& dimension : shape->as<Value::Array>("shape")) {
      const auto* size = dimension.get_if<std::int64_t>();
      if (size == nullptr)
        throw MsgpackError("__ndarray__ shape entry is " + dimension.TypeName() + ", not int", start);
      array.shape.push_back(*size);
    }
    try {
      CheckNdArraySize(array);
    } catch (const std::invalid_argument& error) {
      throw MsgpackError(error.what(), start);
    }
    return array;
  }

  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t position_ = 0;
};

}  // namespace

Value DecodeMsgpack(const std::uint8_t* data, std::size_t size) { return Decoder(data, size).DecodeWhole(); }

}  // namespace tavis::batch::remote
