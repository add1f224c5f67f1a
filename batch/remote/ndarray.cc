#include "batch/remote/ndarray.h"

#include <cstring>
#include <limits>
#include <stdexcept>
#include <string_view>

namespace tavis::batch::remote {
namespace {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "ndarray bytes are copied as host floats, which must be little-endian like '<f4'");

template <typename T>
NdArray MakeArray(const char* dtype, std::vector<std::int64_t> shape, const std::vector<T>& values) {
  NdArray array{dtype, std::move(shape), std::vector<std::uint8_t>(values.size() * sizeof(T))};
  if (!values.empty()) std::memcpy(array.data.data(), values.data(), array.data.size());
  CheckNdArraySize(array);
  return array;
}

template <typename T>
std::vector<double> ElementsAsDoubles(const NdArray& array) {
  std::vector<double> values(array.data.size() / sizeof(T));
  for (std::size_t i = 0; i < values.size(); ++i) {
    T element;
    std::memcpy(&element, array.data.data() + i * sizeof(T), sizeof(T));
    values[i] = static_cast<double>(element);
  }
  return values;
}

}  // namespace

std::size_t DtypeItemSize(const std::string& dtype) {
  const auto bad = [&dtype]() {
    return std::invalid_argument("ndarray dtype '" + dtype + "' is not a numpy dtype string like '<f4' or '|u1'");
  };
  if (dtype.size() < 3 || dtype.size() > 12 || std::string_view("<>|=").find(dtype[0]) == std::string_view::npos)
    throw bad();
  std::size_t size = 0;
  for (std::size_t i = 2; i < dtype.size(); ++i) {
    if (dtype[i] < '0' || dtype[i] > '9') throw bad();
    size = size * 10 + static_cast<std::size_t>(dtype[i] - '0');
  }
  if (size == 0) throw bad();
  return dtype[1] == 'U' ? 4 * size : size;
}

std::size_t ElementCount(const std::vector<std::int64_t>& shape) {
  constexpr std::size_t kLimit = std::size_t{1} << 62;
  std::size_t count = 1;
  for (const std::int64_t dimension : shape) {
    if (dimension < 0) throw std::invalid_argument("ndarray dimension " + std::to_string(dimension) + " is negative");
    if (dimension != 0 && count > kLimit / static_cast<std::size_t>(dimension)) {
      throw std::invalid_argument("ndarray shape has more than 2^62 elements (dimension " + std::to_string(dimension) +
                                  ")");
    }
    count *= static_cast<std::size_t>(dimension);
  }
  return count;
}

void CheckNdArraySize(const NdArray& array) {
  const std::size_t item_size = DtypeItemSize(array.dtype);
  const std::size_t count = ElementCount(array.shape);
  if (count > std::numeric_limits<std::size_t>::max() / item_size || count * item_size != array.data.size()) {
    throw std::invalid_argument("ndarray of dtype '" + array.dtype + "' and " + std::to_string(count) +
                                " elements needs " + std::to_string(count) + " x " + std::to_string(item_size) +
                                " bytes, has " + std::to_string(array.data.size()));
  }
}

NdArray MakeUint8Array(std::vector<std::int64_t> shape, std::vector<std::uint8_t> data) {
  NdArray array{"|u1", std::move(shape), std::move(data)};
  CheckNdArraySize(array);
  return array;
}

NdArray MakeFloat32Array(std::vector<std::int64_t> shape, const std::vector<float>& values) {
  return MakeArray("<f4", std::move(shape), values);
}

NdArray MakeFloat64Array(std::vector<std::int64_t> shape, const std::vector<double>& values) {
  return MakeArray("<f8", std::move(shape), values);
}

std::vector<double> FloatArrayToDoubles(const NdArray& array) {
  CheckNdArraySize(array);
  if (array.dtype == "<f4") return ElementsAsDoubles<float>(array);
  if (array.dtype == "<f8") return ElementsAsDoubles<double>(array);
  throw std::invalid_argument("expected a float array of dtype '<f4' or '<f8', got dtype '" + array.dtype + "'");
}

}  // namespace tavis::batch::remote
