#include "batch/remote/msgpack_decoder.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "batch/remote/msgpack_encoder.h"
#include "batch/remote/remote_error.h"
#include "tests/batch/remote/golden_values.h"

namespace tavis::batch::remote {
namespace {

// The MsgpackError that decoding `bytes` throws, as "offset: message".
std::string ErrorOf(const std::vector<std::uint8_t>& bytes) {
  try {
    DecodeMsgpack(bytes);
  } catch (const MsgpackError& error) {
    return std::to_string(error.offset()) + ": " + error.what();
  }
  return "no error";
}

std::vector<std::uint8_t> NdArrayMapWith(const std::string& dtype, Value::Array shape, std::vector<std::uint8_t> data) {
  return EncodeMsgpack(Value::Map{{Binary::Of("__ndarray__"), true},
                                  {Binary::Of("data"), Binary{std::move(data)}},
                                  {Binary::Of("dtype"), dtype},
                                  {Binary::Of("shape"), std::move(shape)}});
}

TEST(MsgpackDecoder, TruncationNamesWhatAndWhere) {
  EXPECT_EQ(ErrorOf({}), "0: msgpack: truncated type marker: needs 1 bytes, 0 left at byte offset 0");
  EXPECT_EQ(ErrorOf({0x92, 0x01}), "1: msgpack: truncated array entries: needs 2 bytes, 1 left at byte offset 1");
  EXPECT_EQ(ErrorOf({0x82, 0x01, 0x02, 0x03, 0xcd}),
            "5: msgpack: truncated uint16: needs 2 bytes, 0 left at byte offset 5");
  EXPECT_EQ(ErrorOf({0xa5, 'a', 'b'}), "1: msgpack: truncated str payload: needs 5 bytes, 2 left at byte offset 1");
  EXPECT_EQ(ErrorOf({0xcb, 0x3f}), "1: msgpack: truncated float64: needs 8 bytes, 1 left at byte offset 1");
}

TEST(MsgpackDecoder, ForgedHugeLengthsFailBeforeAllocating) {
  EXPECT_EQ(ErrorOf({0xdd, 0xff, 0xff, 0xff, 0xff, 0xc0}),
            "5: msgpack: truncated array entries: needs 4294967295 bytes, 1 left at byte offset 5");
  EXPECT_EQ(ErrorOf({0xdf, 0xff, 0xff, 0xff, 0xff}),
            "5: msgpack: truncated map entries: needs 8589934590 bytes, 0 left at byte offset 5");
  EXPECT_EQ(ErrorOf({0xc6, 0x7f, 0xff, 0xff, 0xff}),
            "5: msgpack: truncated bin payload: needs 2147483647 bytes, 0 left at byte offset 5");
}

TEST(MsgpackDecoder, RejectsTrailingBytesExtTypesAndTheUnusedMarker) {
  EXPECT_EQ(ErrorOf({0xc0, 0xc0}), "1: msgpack: 1 trailing bytes after the value at byte offset 1");
  EXPECT_EQ(ErrorOf({0x91, 0xd4, 0x01, 0x00}), "1: msgpack: unsupported ext type marker 0xd4 at byte offset 1");
  EXPECT_EQ(ErrorOf({0xc1}), "0: msgpack: never-used marker 0xc1 at byte offset 0");
}

TEST(MsgpackDecoder, LimitsNesting) {
  std::vector<std::uint8_t> deep(kMaxMsgpackDepth + 2, 0x91);
  deep.push_back(0xc0);
  EXPECT_NE(ErrorOf(deep).find("nesting deeper than 512"), std::string::npos) << ErrorOf(deep);
  std::vector<std::uint8_t> allowed(kMaxMsgpackDepth, 0x91);
  allowed.push_back(0xc0);
  EXPECT_NO_THROW(DecodeMsgpack(allowed));
}

TEST(MsgpackDecoder, MalformedNumpyMapsNameTheFaultAtTheMapStart) {
  EXPECT_EQ(ErrorOf(NdArrayMapWith("<f4", {2}, {0, 0, 0, 0})),
            "0: msgpack: ndarray of dtype '<f4' and 2 elements needs 2 x 4 bytes, has 4 at byte offset 0");
  EXPECT_EQ(ErrorOf(NdArrayMapWith("float", {1}, {0})),
            "0: msgpack: ndarray dtype 'float' is not a numpy dtype string like '<f4' or '|u1' at byte offset 0");
  EXPECT_EQ(ErrorOf(NdArrayMapWith("|u1", {-1}, {})), "0: msgpack: ndarray dimension -1 is negative at byte offset 0");
  EXPECT_EQ(ErrorOf(NdArrayMapWith("|u1", {"3"}, {0, 0, 0})),
            "0: msgpack: __ndarray__ shape entry is str, not int at byte offset 0");
  std::vector<std::uint8_t> nested = {0x91};
  const std::vector<std::uint8_t> no_data = EncodeMsgpack(Value::Map{
      {Binary::Of("__ndarray__"), true}, {Binary::Of("dtype"), "|u1"}, {Binary::Of("shape"), Value::Array{}}});
  nested.insert(nested.end(), no_data.begin(), no_data.end());
  EXPECT_EQ(ErrorOf(nested), "1: msgpack: __ndarray__ map needs bin 'data' at byte offset 1");
}

TEST(MsgpackDecoder, NumpyScalarsBecomeTheirItem) {
  EXPECT_TRUE(DecodeMsgpack(EncodeMsgpack(Value::Map{
                  {Binary::Of("__npgeneric__"), true}, {Binary::Of("data"), 7}, {Binary::Of("dtype"), "<i8"}})) ==
              Value(7));
}

TEST(MsgpackDecoder, IntegersKeepTheirValueAcrossWidths) {
  EXPECT_TRUE(DecodeMsgpack({0xcd, 0x00, 0x05}) == Value(5));  // a non-shortest uint16 is still 5
  EXPECT_TRUE(DecodeMsgpack({0xd3, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xfe}) == Value(-2));
  EXPECT_TRUE(DecodeMsgpack({0xcf, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff}).is<std::uint64_t>());
}

TEST(MsgpackValue, AccessorsNameTheExpectedAndActualTypes) {
  const Value reply = testing::StrMap({{"actions", MakeFloat32Array({1, 2}, {0.5F, 1.5F})}, {"prompt", "go"}});
  EXPECT_EQ(reply.Find("actions")->as<NdArray>("actions").shape, (std::vector<std::int64_t>{1, 2}));
  EXPECT_EQ(reply.Find("missing"), nullptr);
  try {
    reply.Find("prompt")->as<NdArray>("reply \"prompt\"");
    FAIL() << "no error";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "reply \"prompt\": expected ndarray, got str");
  }
  EXPECT_EQ(NumberAsDouble(Value(2.5F), "x"), 2.5);
  EXPECT_THROW(NumberAsDouble(Value("2"), "x"), std::invalid_argument);
}

TEST(NdArray, ChecksSizesAndConvertsFloats) {
  EXPECT_EQ(DtypeItemSize("<U2"), 8U);
  EXPECT_EQ(DtypeItemSize("|u1"), 1U);
  EXPECT_THROW(DtypeItemSize("<f"), std::invalid_argument);
  EXPECT_THROW(MakeUint8Array({2, 2}, {1, 2, 3}), std::invalid_argument);
  EXPECT_EQ(FloatArrayToDoubles(MakeFloat32Array({2}, {0.1F, -2.0F})),
            (std::vector<double>{static_cast<double>(0.1F), -2.0}));
  try {
    FloatArrayToDoubles(MakeUint8Array({1}, {1}));
    FAIL() << "no error";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "expected a float array of dtype '<f4' or '<f8', got dtype '|u1'");
  }
}

}  // namespace
}  // namespace tavis::batch::remote
