// Test support: the values golden_msgpack.py encodes in Python, built here in C++ under the same
// names, so the golden test can compare our bytes with python3-msgpack's and the fuzz test can
// start from valid messages.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "batch/remote/msgpack_value.h"

namespace tavis::batch::remote::testing {

struct GoldenCase {
  std::string name;
  Value value;    // what we encode
  Value decoded;  // what decoding Python's bytes must give (differs for numpy scalars)
};

std::vector<GoldenCase> GoldenCases();

// (i % modulus) for each element of `shape`, as golden_msgpack.py's pattern().
NdArray PatternImage(std::vector<std::int64_t> shape, int modulus = 251);

// A map from str keys, in order.
Value StrMap(std::vector<std::pair<std::string, Value>> entries);

}  // namespace tavis::batch::remote::testing
