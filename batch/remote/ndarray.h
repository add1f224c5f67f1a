// A numpy array as openpi's msgpack-numpy carries it: numpy's dtype string (`arr.dtype.str`,
// e.g. "|u1", "<f4", "<f8"), the shape, and the C-order bytes (`arr.tobytes()`).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace tavis::batch::remote {

struct NdArray {
  std::string dtype;
  std::vector<std::int64_t> shape;
  std::vector<std::uint8_t> data;

  bool operator==(const NdArray& other) const {
    return dtype == other.dtype && shape == other.shape && data == other.data;
  }
};

// Bytes per element of a numpy dtype string "<byte order><kind><size>" ("<U2" is 8: UCS-4).
// Throws std::invalid_argument naming the string when it is not of that form.
std::size_t DtypeItemSize(const std::string& dtype);

// Elements in `shape` (1 for a 0-d array). Throws std::invalid_argument naming a negative
// dimension or a product beyond 2^62.
std::size_t ElementCount(const std::vector<std::int64_t>& shape);

// Throws std::invalid_argument unless data.size() == ElementCount(shape) * DtypeItemSize(dtype),
// the condition numpy's np.ndarray(buffer=...) needs on the Python side.
void CheckNdArraySize(const NdArray& array);

NdArray MakeUint8Array(std::vector<std::int64_t> shape, std::vector<std::uint8_t> data);
NdArray MakeFloat32Array(std::vector<std::int64_t> shape, const std::vector<float>& values);
NdArray MakeFloat64Array(std::vector<std::int64_t> shape, const std::vector<double>& values);

// The elements of a little-endian float32 ("<f4") or float64 ("<f8") array as doubles; any other
// dtype throws std::invalid_argument naming it.
std::vector<double> FloatArrayToDoubles(const NdArray& array);

}  // namespace tavis::batch::remote
