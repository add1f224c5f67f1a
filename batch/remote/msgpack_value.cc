#include "batch/remote/msgpack_value.h"

#include <array>
#include <stdexcept>

namespace tavis::batch::remote {

std::string Value::TypeNameOf(std::size_t index) {
  static constexpr std::array<const char*, std::variant_size_v<Storage>> kNames = {
      "None", "bool", "int", "int", "float32", "float", "str", "bytes", "list", "dict", "ndarray"};
  return kNames.at(index);
}

const Value* Value::Find(std::string_view key) const {
  const Map* entries = get_if<Map>();
  if (entries == nullptr) return nullptr;
  for (const MapEntry& entry : *entries) {
    if (const std::string* text = entry.key.get_if<std::string>(); text != nullptr && *text == key) {
      return &entry.value;
    }
    if (const Binary* bytes = entry.key.get_if<Binary>();
        bytes != nullptr &&
        std::string_view(reinterpret_cast<const char*>(bytes->bytes.data()), bytes->bytes.size()) == key) {
      return &entry.value;
    }
  }
  return nullptr;
}

bool Value::operator==(const Value& other) const { return storage_ == other.storage_; }

double NumberAsDouble(const Value& value, std::string_view what) {
  if (const auto* number = value.get_if<double>()) return *number;
  if (const auto* number = value.get_if<float>()) return static_cast<double>(*number);
  if (const auto* number = value.get_if<std::int64_t>()) return static_cast<double>(*number);
  if (const auto* number = value.get_if<std::uint64_t>()) return static_cast<double>(*number);
  throw std::invalid_argument(std::string(what) + ": expected a number, got " + value.TypeName());
}

}  // namespace tavis::batch::remote
