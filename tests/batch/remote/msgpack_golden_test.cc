// Our msgpack bytes against independent producers: python3-msgpack with openpi's msgpack-numpy
// hook (golden_msgpack.py, run now by /usr/bin/python3), and the hex dumps of
// policy-interfaces.md §A1 (experiment E1).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <sstream>
#include <string>

#include "batch/remote/msgpack_decoder.h"
#include "batch/remote/msgpack_encoder.h"
#include "tests/batch/remote/golden_values.h"
#include "tests/batch/remote/test_scripts.h"

namespace tavis::batch::remote {
namespace {

std::vector<std::uint8_t> FromHex(const std::string& hex) {
  std::vector<std::uint8_t> bytes;
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2)
    bytes.push_back(static_cast<std::uint8_t>(std::stoi(hex.substr(i, 2), nullptr, 16)));
  return bytes;
}

std::string ToHex(const std::vector<std::uint8_t>& bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string hex;
  for (const std::uint8_t byte : bytes) hex += {kDigits[byte >> 4], kDigits[byte & 0xf]};
  return hex;
}

// NAME -> bytes, as python3-msgpack encodes them.
const std::map<std::string, std::vector<std::uint8_t>>& PythonEncodings() {
  static const std::map<std::string, std::vector<std::uint8_t>> encodings = [] {
    tavis::testing::ChildProcess script(tavis::testing::kDebianPython, {testing::TestScript("golden_msgpack.py")},
                                        testing::kPythonHint);
    std::istringstream lines(script.ReadAllOutput(std::chrono::seconds(60)));
    std::map<std::string, std::vector<std::uint8_t>> parsed;
    std::string name, hex;
    while (lines >> name >> hex) parsed[name] = FromHex(hex);
    return parsed;
  }();
  return encodings;
}

TEST(MsgpackGolden, EncodingIsByteIdenticalToPythonMsgpack) {
  const auto& python = PythonEncodings();
  const std::vector<testing::GoldenCase> cases = testing::GoldenCases();
  ASSERT_EQ(python.size(), cases.size()) << "golden_msgpack.py and golden_values.cc list different cases";
  for (const testing::GoldenCase& golden : cases) {
    ASSERT_EQ(python.count(golden.name), 1U) << golden.name << " missing from golden_msgpack.py";
    const std::vector<std::uint8_t> ours = EncodeMsgpack(golden.value);
    const std::vector<std::uint8_t>& theirs = python.at(golden.name);
    EXPECT_EQ(ours.size(), theirs.size()) << golden.name;
    EXPECT_TRUE(ours == theirs) << golden.name << "\n ours:   " << ToHex(ours).substr(0, 400)
                                << "\n python: " << ToHex(theirs).substr(0, 400);
  }
}

TEST(MsgpackGolden, DecodesPythonBytesToTheSameValues) {
  const auto& python = PythonEncodings();
  for (const testing::GoldenCase& golden : testing::GoldenCases()) {
    const Value decoded = DecodeMsgpack(python.at(golden.name));
    EXPECT_TRUE(decoded == golden.decoded) << golden.name << " decoded as " << decoded.TypeName();
    // Also bit for bit (tells -0.0 from 0.0, float32 from float64).
    EXPECT_TRUE(EncodeMsgpack(decoded) == EncodeMsgpack(golden.decoded)) << golden.name;
  }
}

TEST(MsgpackGolden, NumpyArraysDecodeToNdArrayOnlyWithBinKeys) {
  const auto& python = PythonEncodings();
  const Value image = DecodeMsgpack(python.at("image_224"));
  ASSERT_TRUE(image.is<NdArray>());
  EXPECT_EQ(image.get_if<NdArray>()->dtype, "|u1");
  EXPECT_EQ(image.get_if<NdArray>()->shape, (std::vector<std::int64_t>{224, 224, 3}));
  EXPECT_EQ(image.get_if<NdArray>()->data[250], 250);
  EXPECT_EQ(image.get_if<NdArray>()->data[251], 0);
  const Value plain = DecodeMsgpack(python.at("str_keys_stay_a_map"));
  ASSERT_TRUE(plain.is<Value::Map>());
  EXPECT_EQ(plain.Find("dtype")->as<std::string>("dtype"), "|u1");
}

// The hex dumps printed in policy-interfaces.md §A1, a source independent of the Python run.
TEST(MsgpackGolden, EncodingMatchesTheReferenceHexDumps) {
  EXPECT_EQ(ToHex(EncodeMsgpack(MakeFloat32Array({2}, {1.0F, 2.0F}))),
            "84"
            "c40b5f5f6e6461727261795f5f"
            "c3"
            "c40464617461"
            "c4080000803f00000040"
            "c4056474797065"
            "a33c6634"
            "c4057368617065"
            "9102");
  EXPECT_EQ(ToHex(EncodeMsgpack(Value::Array{1.0, 3, -1, 300, true, nullptr})), "96cb3ff000000000000003ffcd012cc3c0");
  EXPECT_EQ(ToHex(EncodeMsgpack(Value::Map{})), "80");
  const std::string image = ToHex(EncodeMsgpack(testing::PatternImage({224, 224, 3})));
  EXPECT_EQ(image.size(), 2U * 150578U);
  EXPECT_EQ(image.substr(42, 10), "c600024c00");  // bin32 of 150,528 bytes after the two keys
  EXPECT_EQ(image.substr(image.size() - 48), "c4056474797065a37c7531c405736861706593cce0cce003");
}

TEST(MsgpackGolden, PythonNanBytesDecodeToNan) {
  const Value nan = DecodeMsgpack(FromHex("cb7ff8000000000000"));
  ASSERT_TRUE(nan.is<double>());
  EXPECT_TRUE(std::isnan(*nan.get_if<double>()));
  EXPECT_EQ(ToHex(EncodeMsgpack(nan)), "cb7ff8000000000000");
}

}  // namespace
}  // namespace tavis::batch::remote
