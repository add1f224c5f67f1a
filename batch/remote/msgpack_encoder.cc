#include "batch/remote/msgpack_encoder.h"

#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace tavis::batch::remote {
namespace {

void AppendBigEndian(std::uint64_t number, int bytes, std::vector<std::uint8_t>& out) {
  for (int shift = 8 * (bytes - 1); shift >= 0; shift -= 8) out.push_back(static_cast<std::uint8_t>(number >> shift));
}

// A one-byte marker followed by a big-endian number of `bytes` bytes.
void AppendTagged(std::uint8_t marker, std::uint64_t number, int bytes, std::vector<std::uint8_t>& out) {
  out.push_back(marker);
  AppendBigEndian(number, bytes, out);
}

void AppendUnsigned(std::uint64_t number, std::vector<std::uint8_t>& out) {
  if (number < 0x80) {
    out.push_back(static_cast<std::uint8_t>(number));
  } else if (number <= 0xff) {
    AppendTagged(0xcc, number, 1, out);
  } else if (number <= 0xffff) {
    AppendTagged(0xcd, number, 2, out);
  } else if (number <= 0xffffffff) {
    AppendTagged(0xce, number, 4, out);
  } else {
    AppendTagged(0xcf, number, 8, out);
  }
}

void AppendSigned(std::int64_t number, std::vector<std::uint8_t>& out) {
  if (number >= 0) return AppendUnsigned(static_cast<std::uint64_t>(number), out);
  const auto bits = static_cast<std::uint64_t>(number);
  if (number >= -32) {
    out.push_back(static_cast<std::uint8_t>(bits));
  } else if (number >= std::numeric_limits<std::int8_t>::min()) {
    AppendTagged(0xd0, bits, 1, out);
  } else if (number >= std::numeric_limits<std::int16_t>::min()) {
    AppendTagged(0xd1, bits, 2, out);
  } else if (number >= std::numeric_limits<std::int32_t>::min()) {
    AppendTagged(0xd2, bits, 4, out);
  } else {
    AppendTagged(0xd3, bits, 8, out);
  }
}

// The header of a str, bin, array or map of `size` entries: `fix_marker | size` below
// `fix_limit` (0 when the type has no fix form), else the 8- (if any), 16- or 32-bit form.
struct LengthMarkers {
  const char* type;
  std::uint8_t fix_marker;
  std::size_t fix_limit;
  std::uint8_t marker8;  // 0 when there is no 8-bit form
  std::uint8_t marker16;
  std::uint8_t marker32;
};
constexpr LengthMarkers kStr{"str", 0xa0, 32, 0xd9, 0xda, 0xdb};
constexpr LengthMarkers kBin{"bin", 0, 0, 0xc4, 0xc5, 0xc6};
constexpr LengthMarkers kArray{"array", 0x90, 16, 0, 0xdc, 0xdd};
constexpr LengthMarkers kMap{"map", 0x80, 16, 0, 0xde, 0xdf};

void AppendLength(const LengthMarkers& markers, std::size_t size, std::vector<std::uint8_t>& out) {
  if (size < markers.fix_limit) {
    out.push_back(static_cast<std::uint8_t>(markers.fix_marker | size));
  } else if (markers.marker8 != 0 && size <= 0xff) {
    AppendTagged(markers.marker8, size, 1, out);
  } else if (size <= 0xffff) {
    AppendTagged(markers.marker16, size, 2, out);
  } else if (size <= 0xffffffff) {
    AppendTagged(markers.marker32, size, 4, out);
  } else {
    throw std::invalid_argument(std::string("msgpack ") + markers.type + " of " + std::to_string(size) +
                                " entries exceeds the 2^32 - 1 limit");
  }
}

void AppendBytes(const LengthMarkers& markers, const void* data, std::size_t size, std::vector<std::uint8_t>& out) {
  AppendLength(markers, size, out);
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  out.insert(out.end(), bytes, bytes + size);
}

void AppendBinKey(const char* key, std::vector<std::uint8_t>& out) { AppendBytes(kBin, key, std::strlen(key), out); }

// openpi's pack_array: {b"__ndarray__": True, b"data": bytes, b"dtype": str, b"shape": [ints]}.
void AppendNdArray(const NdArray& array, std::vector<std::uint8_t>& out) {
  CheckNdArraySize(array);
  AppendLength(kMap, 4, out);
  AppendBinKey("__ndarray__", out);
  out.push_back(0xc3);
  AppendBinKey("data", out);
  AppendBytes(kBin, array.data.data(), array.data.size(), out);
  AppendBinKey("dtype", out);
  AppendBytes(kStr, array.dtype.data(), array.dtype.size(), out);
  AppendBinKey("shape", out);
  AppendLength(kArray, array.shape.size(), out);
  for (const std::int64_t dimension : array.shape) AppendSigned(dimension, out);
}

template <typename Float, typename Bits>
void AppendFloat(std::uint8_t marker, Float number, std::vector<std::uint8_t>& out) {
  Bits bits;
  std::memcpy(&bits, &number, sizeof bits);
  AppendTagged(marker, bits, sizeof bits, out);
}

// The str, bin and ndarray payload bytes in `value`: nearly all of a request's size.
std::size_t BulkBytes(const Value& value) {
  if (const auto* array = value.get_if<NdArray>()) return array->data.size();
  if (const auto* binary = value.get_if<Binary>()) return binary->bytes.size();
  if (const auto* text = value.get_if<std::string>()) return text->size();
  std::size_t total = 0;
  if (const auto* items = value.get_if<Value::Array>()) {
    for (const Value& item : *items) total += BulkBytes(item);
  }
  if (const auto* entries = value.get_if<Value::Map>()) {
    for (const MapEntry& entry : *entries) total += BulkBytes(entry.key) + BulkBytes(entry.value);
  }
  return total;
}

}  // namespace

void AppendMsgpack(const Value& value, std::vector<std::uint8_t>& out) {
  const Value::Storage& storage = value.storage();
  if (value.is<std::nullptr_t>()) {
    out.push_back(0xc0);
  } else if (const auto* flag = std::get_if<bool>(&storage)) {
    out.push_back(*flag ? 0xc3 : 0xc2);
  } else if (const auto* signed_number = std::get_if<std::int64_t>(&storage)) {
    AppendSigned(*signed_number, out);
  } else if (const auto* unsigned_number = std::get_if<std::uint64_t>(&storage)) {
    AppendUnsigned(*unsigned_number, out);
  } else if (const auto* single = std::get_if<float>(&storage)) {
    AppendFloat<float, std::uint32_t>(0xca, *single, out);
  } else if (const auto* number = std::get_if<double>(&storage)) {
    AppendFloat<double, std::uint64_t>(0xcb, *number, out);
  } else if (const auto* text = std::get_if<std::string>(&storage)) {
    AppendBytes(kStr, text->data(), text->size(), out);
  } else if (const auto* binary = std::get_if<Binary>(&storage)) {
    AppendBytes(kBin, binary->bytes.data(), binary->bytes.size(), out);
  } else if (const auto* items = std::get_if<Value::Array>(&storage)) {
    AppendLength(kArray, items->size(), out);
    for (const Value& item : *items) AppendMsgpack(item, out);
  } else if (const auto* entries = std::get_if<Value::Map>(&storage)) {
    AppendLength(kMap, entries->size(), out);
    for (const MapEntry& entry : *entries) {
      AppendMsgpack(entry.key, out);
      AppendMsgpack(entry.value, out);
    }
  } else {
    AppendNdArray(std::get<NdArray>(storage), out);
  }
}

std::vector<std::uint8_t> EncodeMsgpack(const Value& value) {
  std::vector<std::uint8_t> out;
  out.reserve(BulkBytes(value) + 4096);  // one allocation for megabytes of images, not a dozen
  AppendMsgpack(value, out);
  return out;
}

}  // namespace tavis::batch::remote
