#include "tests/batch/remote/golden_values.h"

#include <cstring>
#include <limits>

namespace tavis::batch::remote::testing {
namespace {

Value Repeated(std::size_t count, const Value& item) { return Value::Array(count, item); }

Value NumberedMap(int count) {
  Value::Map entries;
  for (int i = 0; i < count; ++i) entries.push_back({std::to_string(i), i});
  return entries;
}

Value IntEdges() {
  return Value::Array{0,
                      127,
                      128,
                      255,
                      256,
                      65535,
                      65536,
                      4294967295LL,
                      4294967296LL,
                      std::numeric_limits<std::int64_t>::max(),
                      std::numeric_limits<std::uint64_t>::max(),
                      -1,
                      -32,
                      -33,
                      -128,
                      -129,
                      -32768,
                      -32769,
                      -2147483648LL,
                      -2147483649LL,
                      std::numeric_limits<std::int64_t>::min()};
}

NdArray Int64Pair() {
  const std::int64_t values[2] = {1, -2};
  NdArray array{"<i8", {2}, std::vector<std::uint8_t>(sizeof values)};
  std::memcpy(array.data.data(), values, sizeof values);
  return array;
}

}  // namespace

NdArray PatternImage(std::vector<std::int64_t> shape, int modulus) {
  std::size_t count = 1;
  for (const std::int64_t dimension : shape) count *= static_cast<std::size_t>(dimension);
  std::vector<std::uint8_t> data(count);
  for (std::size_t i = 0; i < count; ++i) data[i] = static_cast<std::uint8_t>(i % static_cast<std::size_t>(modulus));
  return MakeUint8Array(std::move(shape), std::move(data));
}

Value StrMap(std::vector<std::pair<std::string, Value>> entries) {
  Value::Map map;
  for (auto& [key, value] : entries) map.push_back({key, std::move(value)});
  return map;
}

std::vector<GoldenCase> GoldenCases() {
  const Value doubles = Value::Array{0.0, -0.0, 1.5, 1e300, std::numeric_limits<double>::infinity()};
  const Value mixed = Value::Array{1.0, 3, -1, 300, true, nullptr};
  const Value npgeneric =
      Value::Map{{Binary::Of("__npgeneric__"), true}, {Binary::Of("data"), 0.5}, {Binary::Of("dtype"), "<f4"}};
  const Value strings = Value::Array{"",
                                     std::string(31, 'a'),
                                     std::string(32, 'b'),
                                     std::string(255, 'c'),
                                     std::string(256, 'd'),
                                     std::string(65536, 'e'),
                                     "h\xc3\xa9llo"};
  const Value binaries =
      Value::Array{Binary{}, Binary{std::vector<std::uint8_t>(255, 0)}, Binary{std::vector<std::uint8_t>(256, 1)},
                   Binary{std::vector<std::uint8_t>(65536, 2)}};
  const Value containers = Value::Array{Repeated(15, nullptr), Repeated(16, nullptr), Repeated(65536, nullptr),
                                        NumberedMap(15), NumberedMap(16)};
  const Value str_keys =
      StrMap({{"__ndarray__", true}, {"data", Binary{{7}}}, {"dtype", "|u1"}, {"shape", Value::Array{1}}});
  const Value libero =
      StrMap({{"observation/image", PatternImage({8, 6, 3})},
              {"observation/wrist_image", PatternImage({8, 6, 3}, 13)},
              {"observation/state", MakeFloat32Array({8}, {0.5F, -1.25F, 2.0F, 0.0F, 1.0F, -3.5F, 0.04F, 0.04F})},
              {"prompt", "pick up the red cube"}});
  std::vector<float> aloha_state(14);
  for (int i = 0; i < 14; ++i) aloha_state[i] = static_cast<float>(i) / 4;
  const Value aloha = StrMap({{"state", MakeFloat32Array({14}, aloha_state)},
                              {"images", StrMap({{"cam_high", PatternImage({3, 4, 4})}})},
                              {"prompt", "fold"}});
  std::vector<double> actions(70);
  for (int i = 0; i < 70; ++i) actions[i] = i / 8.0;
  const Value reply = StrMap({{"actions", MakeFloat64Array({10, 7}, actions)},
                              {"policy_timing", StrMap({{"infer_ms", 12.5}})},
                              {"server_timing", StrMap({{"infer_ms", 13.25}, {"prev_total_ms", 20.0}})}});

  return {
      {"f32_pair", MakeFloat32Array({2}, {1.0F, 2.0F}), MakeFloat32Array({2}, {1.0F, 2.0F})},
      {"image_224", PatternImage({224, 224, 3}), PatternImage({224, 224, 3})},
      {"empty_map", Value::Map{}, Value::Map{}},
      {"mixed_list", mixed, mixed},
      {"npgeneric_f32", npgeneric, 0.5},
      {"zero_d_f8", MakeFloat64Array({}, {2.5}), MakeFloat64Array({}, {2.5})},
      {"empty_rows_f4", MakeFloat32Array({0, 3}, {}), MakeFloat32Array({0, 3}, {})},
      {"int64_array", Int64Pair(), Int64Pair()},
      {"int_edges", IntEdges(), IntEdges()},
      {"doubles", doubles, doubles},
      {"strings", strings, strings},
      {"binaries", binaries, binaries},
      {"containers", containers, containers},
      {"str_keys_stay_a_map", str_keys, str_keys},
      {"libero_observation", libero, libero},
      {"aloha_observation", aloha, aloha},
      {"reply_f8", reply, reply},
      {"single_floats", Value::Array{1.5F, -0.25F}, Value::Array{1.5F, -0.25F}},
  };
}

}  // namespace tavis::batch::remote::testing
