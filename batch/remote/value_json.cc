#include "batch/remote/value_json.h"

#include <cmath>
#include <type_traits>

namespace tavis::batch::remote {
namespace {

nlohmann::json Number(double number) {
  if (std::isfinite(number)) return number;
  return std::isnan(number) ? "nan" : (number > 0 ? "inf" : "-inf");
}

}  // namespace

nlohmann::json ToJson(const Value& value) {
  return std::visit(
      [](const auto& item) -> nlohmann::json {
        using T = std::decay_t<decltype(item)>;
        if constexpr (std::is_same_v<T, std::nullptr_t>) {
          return nullptr;
        } else if constexpr (std::is_same_v<T, float> || std::is_same_v<T, double>) {
          return Number(static_cast<double>(item));
        } else if constexpr (std::is_same_v<T, Binary>) {
          return {{"bytes", item.bytes.size()}};
        } else if constexpr (std::is_same_v<T, NdArray>) {
          return {{"ndarray", {{"dtype", item.dtype}, {"shape", item.shape}}}};
        } else if constexpr (std::is_same_v<T, Value::Array>) {
          nlohmann::json array = nlohmann::json::array();
          for (const Value& element : item) array.push_back(ToJson(element));
          return array;
        } else if constexpr (std::is_same_v<T, Value::Map>) {
          nlohmann::json object = nlohmann::json::object();
          for (const MapEntry& entry : item) {
            const std::string* key = entry.key.get_if<std::string>();
            object[key != nullptr ? *key : ToJson(entry.key).dump()] = ToJson(entry.value);
          }
          return object;
        } else {
          return item;  // bool, integers, str
        }
      },
      value.storage());
}

}  // namespace tavis::batch::remote
