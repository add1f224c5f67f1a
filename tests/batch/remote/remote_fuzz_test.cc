// Bounded random-input tests of the two parsers that read bytes from the network: up to 100,000
// random and mutated inputs each, for at most two seconds. Any outcome other than a value or the
// parser's own exception type (a crash, std::bad_alloc, std::length_error, ...) fails the test.
// The generator is seeded, so a failure reproduces.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <random>
#include <vector>

#include "batch/remote/msgpack_decoder.h"
#include "batch/remote/msgpack_encoder.h"
#include "batch/remote/remote_error.h"
#include "batch/remote/websocket_frame.h"
#include "batch/remote/websocket_reader.h"
#include "tests/batch/remote/golden_values.h"

namespace tavis::batch::remote {
namespace {

using Bytes = std::vector<std::uint8_t>;

constexpr int kMaxInputs = 100'000;
constexpr auto kTimeBudget = std::chrono::milliseconds(2000);
constexpr int kMinInputs = 1'000;

class Mutator {
 public:
  explicit Mutator(std::vector<Bytes> seeds) : seeds_(std::move(seeds)) {}

  // A seed changed by a few random edits, or, one time in eight, plain random bytes.
  Bytes Next() {
    if (Pick(8) == 0) {
      Bytes noise(Pick(64));
      for (std::uint8_t& byte : noise) byte = static_cast<std::uint8_t>(Pick(256));
      return noise;
    }
    Bytes input = seeds_[Pick(seeds_.size())];
    const std::size_t edits = 1 + Pick(4);
    for (std::size_t edit = 0; edit < edits && !input.empty(); ++edit) {
      const std::size_t at = Pick(input.size());
      switch (Pick(5)) {
        case 0: input[at] = static_cast<std::uint8_t>(Pick(256)); break;
        case 1: input[at] ^= static_cast<std::uint8_t>(1U << Pick(8)); break;
        case 2: input.resize(at); break;
        case 3:
          input.insert(input.begin() + static_cast<std::ptrdiff_t>(at), static_cast<std::uint8_t>(Pick(256)));
          break;
        default: input[at] = kInteresting[Pick(sizeof kInteresting)]; break;  // length and type markers
      }
    }
    return input;
  }

  std::size_t Pick(std::size_t bound) { return std::uniform_int_distribution<std::size_t>(0, bound - 1)(generator_); }

 private:
  static constexpr std::uint8_t kInteresting[] = {0x00, 0x7e, 0x7f, 0x80, 0xc1, 0xc4, 0xc6, 0xca,
                                                  0xdb, 0xdd, 0xdf, 0xff, 0xd4, 0x91, 0x8f};
  std::vector<Bytes> seeds_;
  std::mt19937_64 generator_{20261123};
};

// Runs `check` on mutated inputs until kMaxInputs or the time budget; returns the count.
template <typename Check>
int RunBounded(Mutator& mutator, Check check) {
  const auto deadline = std::chrono::steady_clock::now() + kTimeBudget;
  int inputs = 0;
  while (inputs < kMaxInputs && std::chrono::steady_clock::now() < deadline) {
    check(mutator.Next());
    ++inputs;
  }
  return inputs;
}

std::vector<Bytes> MsgpackSeeds() {
  std::vector<Bytes> seeds;
  for (const testing::GoldenCase& golden : testing::GoldenCases()) {
    Bytes bytes = EncodeMsgpack(golden.value);
    if (bytes.size() <= 4096) seeds.push_back(std::move(bytes));
  }
  seeds.push_back(EncodeMsgpack(Value::Array{Value::Array{Value::Array{1.5F}}, nullptr, false, Binary{{1, 2}}}));
  return seeds;
}

// An unmasked server frame; 7-bit or 64-bit length.
Bytes ServerFrame(std::uint8_t first, const Bytes& payload) {
  const std::size_t header = payload.size() < 126 ? 2 : 10;
  Bytes frame(header + payload.size(), 0);
  frame[0] = first;
  frame[1] = static_cast<std::uint8_t>(header == 2 ? payload.size() : 127);
  for (std::size_t i = 2; i < header; ++i)
    frame[i] = static_cast<std::uint8_t>(payload.size() >> (8 * (header - 1 - i)));
  std::copy(payload.begin(), payload.end(), frame.begin() + static_cast<std::ptrdiff_t>(header));
  return frame;
}

std::vector<Bytes> FrameStreamSeeds() {
  const Bytes binary = ServerFrame(0x82, Bytes(300, 0x11));
  const Bytes fragments = [] {
    Bytes stream = ServerFrame(0x01, {'a', 'b'});
    const Bytes ping = ServerFrame(0x89, {1, 2, 3, 4});
    const Bytes last = ServerFrame(0x80, {'c'});
    stream.insert(stream.end(), ping.begin(), ping.end());
    stream.insert(stream.end(), last.begin(), last.end());
    return stream;
  }();
  const Bytes close = ServerFrame(0x88, {0x03, 0xf3, 'e', 'r', 'r'});
  Bytes all = binary;
  all.insert(all.end(), fragments.begin(), fragments.end());
  all.insert(all.end(), close.begin(), close.end());
  return {binary, fragments, close, all, ServerFrame(0x8a, {}), ServerFrame(0x81, {'x'})};
}

TEST(RemoteFuzz, MsgpackDecoderOnlyThrowsMsgpackError) {
  Mutator mutator(MsgpackSeeds());
  int decoded = 0;
  const int inputs = RunBounded(mutator, [&decoded](const Bytes& input) {
    try {
      const Value value = DecodeMsgpack(input);
      EncodeMsgpack(value);  // whatever decodes must encode again
      ++decoded;
    } catch (const MsgpackError&) {
    }
  });
  std::cout << "[ measure  ] msgpack: " << inputs << " inputs, " << decoded << " decoded\n";
  EXPECT_GE(inputs, kMinInputs);
  EXPECT_GT(decoded, 0);
}

TEST(RemoteFuzz, WebSocketReaderOnlyThrowsProtocolErrors) {
  Mutator mutator(FrameStreamSeeds());
  int events = 0;
  const int inputs = RunBounded(mutator, [&](const Bytes& input) {
    WebSocketReader reader(4096);
    try {
      std::size_t fed = 0;
      while (fed < input.size()) {  // in random-sized pieces, as TCP delivers them
        const std::size_t piece = std::min(input.size() - fed, 1 + mutator.Pick(64));
        reader.Append(input.data() + fed, piece);
        fed += piece;
        while (reader.Next()) ++events;
      }
    } catch (const WebSocketProtocolError&) {
    }
  });
  std::cout << "[ measure  ] websocket: " << inputs << " streams, " << events << " events\n";
  EXPECT_GE(inputs, kMinInputs);
  EXPECT_GT(events, 0);
}

}  // namespace
}  // namespace tavis::batch::remote
