// A decoded msgpack message, typed as openpi's Python side sees it: nil, bool, integers,
// float32/float64, str, bin, array, map (entry order kept, any key type), and numpy arrays
// (msgpack-numpy maps become NdArray when decoded and are emitted as such maps when encoded).
#pragma once

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "batch/remote/ndarray.h"

namespace tavis::batch::remote {

// msgpack bin (Python bytes), kept apart from str (Python str) as use_bin_type=True does.
struct Binary {
  std::vector<std::uint8_t> bytes;

  static Binary Of(std::string_view text) { return {std::vector<std::uint8_t>(text.begin(), text.end())}; }
  bool operator==(const Binary& other) const { return bytes == other.bytes; }
};

struct MapEntry;

class Value {
 public:
  using Array = std::vector<Value>;
  using Map = std::vector<MapEntry>;  // in wire order, as Python dicts keep insertion order
  // Integers that fit int64 are int64 whichever way they were written, so equal numbers compare
  // equal; uint64 holds only those above INT64_MAX.
  using Storage = std::variant<std::nullptr_t, bool, std::int64_t, std::uint64_t, float, double, std::string, Binary,
                               Array, Map, NdArray>;

  Value() : storage_(nullptr) {}
  Value(std::nullptr_t) : storage_(nullptr) {}
  Value(bool flag) : storage_(flag) {}
  template <typename Integer, std::enable_if_t<std::is_integral_v<Integer> && !std::is_same_v<Integer, bool>, int> = 0>
  Value(Integer number) : storage_(FromInteger(number)) {}
  Value(float number) : storage_(number) {}
  Value(double number) : storage_(number) {}
  Value(const char* text) : storage_(std::string(text)) {}
  Value(std::string text) : storage_(std::move(text)) {}
  Value(Binary bytes) : storage_(std::move(bytes)) {}
  Value(Array items) : storage_(std::move(items)) {}
  Value(Map entries) : storage_(std::move(entries)) {}
  Value(NdArray array) : storage_(std::move(array)) {}

  const Storage& storage() const { return storage_; }
  template <typename T>
  const T* get_if() const {
    return std::get_if<T>(&storage_);
  }
  template <typename T>
  bool is() const {
    return std::holds_alternative<T>(storage_);
  }

  // The alternative T; throws std::invalid_argument "<what>: expected <T>, got <actual>".
  template <typename T>
  const T& as(std::string_view what) const {
    if (const T* value = get_if<T>()) return *value;
    throw std::invalid_argument(std::string(what) + ": expected " + TypeNameOf(Value(T{}).storage_.index()) + ", got " +
                                TypeName());
  }

  // Python's name for the type held: "None", "bool", "int", "float32", "float", "str", "bytes",
  // "list", "dict", "ndarray".
  std::string TypeName() const { return TypeNameOf(storage_.index()); }

  // The value of the map entry whose key is the str or bin `key`; null when absent or not a map.
  const Value* Find(std::string_view key) const;

  bool operator==(const Value& other) const;
  bool operator!=(const Value& other) const { return !(*this == other); }

 private:
  template <typename Integer>
  static Storage FromInteger(Integer number) {
    if constexpr (std::is_signed_v<Integer>) {
      return static_cast<std::int64_t>(number);
    } else if (number <= static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
      return static_cast<std::int64_t>(number);
    } else {
      return static_cast<std::uint64_t>(number);
    }
  }
  static std::string TypeNameOf(std::size_t index);

  Storage storage_;
};

struct MapEntry {
  Value key;
  Value value;

  bool operator==(const MapEntry& other) const { return key == other.key && value == other.value; }
};

// A number held as int64, uint64, float32 or float64, as a double; throws std::invalid_argument
// naming `what` and the type for anything else.
double NumberAsDouble(const Value& value, std::string_view what);

}  // namespace tavis::batch::remote
